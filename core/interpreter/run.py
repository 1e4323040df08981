"""What every run loop shares: the programs of a run, the frames of calls and repeated sections, and the end
of a run.

- `Unit`: one program of a run — the main program, a subprogram after it in the same file (PAL `%L<n>`, ISO
  and TRAUB `O<n>`) or one of the program library.
- `Frame`: a run of a unit (or of a section of it) in progress — PAL's L call and G23 section repeat, ISO's
  M98, TRAUB's G22 with P/Q and its macros are all one thing: run blocks `start`…`end` of `callee` so many
  times, then go on at `return_index` of `caller`.
- `finish_toolpath`: the toolpath's lists, the line states of lines no block set, one finding per block and
  the cap on diagnostics.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from core.diagnostics import Diagnostic, diag
from core.interpreter.state import ModalState
from core.syntax.blocks import Block, Program, Span
from core.toolpath import Dwell, Move, ToolChange, Toolpath, Vec3

UnitKey = tuple[str | None, int | None]  # (source, number): (None, None) is the main program


@dataclass(slots=True, eq=False)
class Unit:
    """One program of a run: the main program or a subprogram L<number> / O<number>."""

    number: int | None  # the main program: None (TRAUB: its own O number, if it has one)
    source: str | None  # None: the program file; "L200", "O8000": a file of the program library
    blocks: list[Block]
    line: int = 0  # the line of its header (`%L<n>`, `O<n>`); 0: none (the main program, a library file)
    prefix: str = "L"  # how its programs are called: L (PAL) or O (ISO, TRAUB)
    main: bool = False
    _numbers: dict[int, int] | None = None
    _lines: dict[int, int] | None = None

    @property
    def numbers(self) -> dict[int, int]:
        """Block number N → index of its first block (made when a jump, repeat or section first needs it)."""
        if self._numbers is None:
            self._numbers = {}
            for i, b in enumerate(self.blocks):
                if b.number is not None:
                    self._numbers.setdefault(b.number, i)
        return self._numbers

    def index_of(self, line: int) -> int:
        """The index of its block at `line` (-1: past its last block); KeyError where none is there."""
        if line < 0:
            return len(self.blocks)
        blocks = self.blocks
        if blocks:  # (PAL and ISO units are consecutive lines: found without a map of them)
            i = line - blocks[0].line
            if 0 <= i < len(blocks) and blocks[i].line == line:
                return i
        if self._lines is None:
            self._lines = {b.line: i for i, b in enumerate(self.blocks)}
        return self._lines[line]

    @property
    def first(self) -> int:
        """The line after its header: where its blocks start (PAL and ISO units are consecutive lines)."""
        return self.line + 1

    @property
    def tail(self) -> int:
        """Its last line: the last block's, or the header's when it has no blocks."""
        return self.blocks[-1].line if self.blocks else max(1, self.line)

    @property
    def name(self) -> str:
        return "Hauptprogramm" if self.main else f"{self.prefix}{self.number}"

    @property
    def key(self) -> UnitKey:
        return self.source, None if self.main else self.number


@dataclass(slots=True)
class Frame:
    """A run of `callee` (blocks `start`…`end`, `end` None: to its end or M17/M99) in progress, called from
    the block at `line` of `caller`, which goes on at `return_index`; `remaining` runs follow this one.
    `repeat`: a G23 section of the caller's own blocks, not a call (no call depth, no call stack)."""

    caller: Unit
    return_index: int
    callee: Unit
    start: int
    end: int | None
    remaining: int
    line: int
    repeat: bool = False


@dataclass(slots=True)
class Cursor:
    """Where a run is: the unit, the index of its next block and the frames in progress — and the program flow
    that moves it (calls, repeated sections, returns), the same for every dialect."""

    unit: Unit
    index: int = 0
    frames: list[Frame] = field(default_factory=list)
    returned_from: int = 0  # the calling block's line of the last return

    def calling(self) -> bool:
        """Whether a call is in progress (not only G23 sections of the main program)."""
        return any(not f.repeat for f in self.frames)

    def depth(self) -> int:
        return sum(not f.repeat for f in self.frames)

    def active(self, callee: Unit) -> bool:
        """Whether `callee` runs already (a call of it now would be a recursion)."""
        return callee is self.unit or any(f.callee is callee and not f.repeat for f in self.frames)

    def repeating(self, unit: Unit, line: int) -> bool:
        """Whether the section repeat of `unit`'s block at `line` is in progress (a repeat of it now would be
        nested in itself)."""
        return any(f.repeat and f.line == line and f.caller is unit for f in self.frames)

    def call_stack(self) -> tuple[tuple[str | None, int], ...]:
        """The calling blocks (source, line), outermost first."""
        return tuple((f.caller.source, f.line) for f in self.frames if not f.repeat)

    def enter(self, frame: Frame) -> None:
        """Start a call or a repeated section; `frame.return_index` is where the caller goes on."""
        self.frames.append(frame)
        self.unit, self.index = frame.callee, frame.start

    def after(self, done: int) -> str | None:
        """Block `done` of the unit has run (the calls it made included) and `index` is where the run goes on:
        at the last block of a section, run the section again or go on after the block that called it (which
        may itself end a section). How the run went on: "again" (a section from its start), "returned"
        (after a calling block, whose line is `returned_from`) or None (as it was)."""
        frames = self.frames
        how = None
        while frames and frames[-1].end == done and frames[-1].callee is self.unit:
            top = frames[-1]
            if top.remaining > 0:
                top.remaining -= 1
                self.index = top.start
                return "again"
            frames.pop()
            self.unit, self.index, done = top.caller, top.return_index, top.return_index - 1
            self.returned_from, how = top.line, "returned"
        return how

    def leave(self, again: bool = True) -> str | None:
        """The end of a called program (M17, M99, or past its last block): run it again (`again` and runs to
        come) or go on after the calling block; the program's unfinished G23 sections end with it. How the
        run went on (as `after` says), None when no call is in progress."""
        if not self.calling():
            return None
        frames = self.frames
        while frames[-1].repeat:
            frames.pop()
        frame = frames[-1]
        if again and frame.remaining > 0:
            frame.remaining -= 1
            self.index = frame.start
            return "again"
        frames.pop()
        self.unit, self.index = frame.caller, frame.return_index
        self.returned_from = frame.line
        return self.after(frame.return_index - 1) or "returned"


_SUB_HEADER = {"L": re.compile(r"L\s*(\d+)"), "O": re.compile(r"O(\d+)")}


def split_units(program: Program, prefix: str = "L") -> tuple[Unit, dict[int, Unit]]:
    """The main program and the subprograms that follow it in the same file, each after a `%L<n>` header (PAL) or
    an `O<n>` line (ISO: the O line before the main program's first block is its own number)."""
    pattern = _SUB_HEADER[prefix]
    headers = [
        i for i, b in enumerate(program.blocks) if b.header is not None and pattern.fullmatch(b.header)
    ]
    subs: dict[int, Unit] = {}
    if headers and prefix == "O":
        first = next(
            (i for i, b in enumerate(program.blocks) if b.ok and not b.is_empty and b.header is None),
            len(program.blocks),
        )
        headers = [i for i in headers if i > first]
    if not headers:
        return Unit(None, None, program.blocks, prefix=prefix, main=True), subs
    starts = set(headers)
    main: list[Block] = []
    current = main
    for i, b in enumerate(program.blocks):
        m = pattern.fullmatch(b.header or "") if i in starts else None
        if m is not None:
            current = []
            number = int(m.group(1))
            subs.setdefault(number, Unit(number, None, current, line=b.line, prefix=prefix))
            continue
        current.append(b)
    return Unit(None, None, main, prefix=prefix, main=True), subs


def library_unit(number: int, program: Program, prefix: str) -> Unit:
    """A subprogram of the program library: a file of its own."""
    return Unit(number, f"{prefix}{number}", program.blocks, prefix=prefix)


def program_number(block: Block) -> int | None:
    """TRAUB: the number of an O block (a program's head), else None."""
    if block.words and block.words[0].address == "O" and block.words[0].value is not None:
        return int(block.words[0].value)
    return None


def split_programs(program: Program, source: str | None = None) -> tuple[Unit, list[Unit]]:
    """TRAUB: the main program and the programs after it (`%` … `O8010` … `M99` … `%`, DECISIONS §18).

    An O block starts a new program, except the main program's own number at its head. Lines that are not
    blocks (headers, lines with errors) are no part of a program: a TRAUB unit's blocks are not consecutive.
    """
    main = Unit(None, source, [], line=0, prefix="O", main=source is None)
    others: list[Unit] = []
    current = main
    for b in program.blocks:
        if b.header is not None or not b.ok:
            continue
        number = program_number(b)
        if number is not None:
            if current is main and main.number is None and not any(not x.is_empty for x in main.blocks):
                main.number = number
            else:
                current = Unit(number, source, [], line=b.line, prefix="O")
                others.append(current)
            continue
        current.blocks.append(b)
    return main, others


def dedupe(diags: list[Diagnostic]) -> None:
    """A block run many times (loops, subprograms) reports each finding once."""
    seen: set[tuple[str, Span, str | None]] = set()
    keep = []
    for d in diags:
        key = (d.code, d.span, d.source)
        if key not in seen:
            seen.add(key)
            keep.append(d)
    diags[:] = keep


def finish_toolpath(
    result: Toolpath,
    states: list[ModalState | None],
    positions: list[Vec3 | None],
    start: Vec3,
    answer_only: bool = False,
) -> None:
    """Sort the commands into the toolpath's lists; the lines no block set hold the state and position of the
    line before them (the first ones: the switch-on state at `start`). Nothing of it for a run that makes
    only an answer (RunSetup.answer_only)."""
    if answer_only:
        return
    for command in result.commands:
        if type(command) is Move:
            result.moves.append(command)
        elif type(command) is Dwell:
            result.dwells.append(command)
        elif type(command) is ToolChange:
            result.tool_changes.append(command)
    current_state, current_position = result.initial, start
    for i in range(len(states)):
        st, ps = states[i], positions[i]
        if st is None or ps is None:
            states[i], positions[i] = current_state, current_position
        else:
            current_state, current_position = st, ps
    result.line_states = states  # type: ignore[assignment]
    result.line_positions = positions  # type: ignore[assignment]


def cap_diagnostics(diags: list[Diagnostic], limit: int) -> None:
    """At most `limit` findings: the last one says so."""
    if len(diags) > limit:
        cut = diags[limit - 1]
        del diags[limit - 1 :]
        diags.append(diag("PAL-E012", cut.span, limit=limit))
