"""The machine of PAL, ISO and Beckhoff milling for the run loop (core/interpreter/loop.py): the block
executor (pal_mill.py) with the modal state, position and parameters as values, and what blocks dropped by an
error leave unknown (followups.py)."""

from __future__ import annotations

from typing import Any, Protocol

from core.diagnostics import Diagnostic
from core.dialects.codes import CodeTable
from core.interpreter.checkpoints import LineMap
from core.interpreter.contour import Planned, finish
from core.interpreter.followups import FollowUps
from core.interpreter.loop import FlowCodes, Machine, Step
from core.interpreter.pal_mill import Outcome
from core.interpreter.run import Unit, finish_toolpath, library_unit, split_units
from core.interpreter.state import ModalState, RunSetup, switch_on_state
from core.syntax.blocks import Block, Program
from core.toolpath import Toolpath, Vec3


class BlockExecutor(Protocol):
    def __call__(
        self,
        setup: RunSetup,
        state: ModalState,
        position: Vec3,
        block: Block,
        params: dict[int, float],
        *,
        cache: dict[Any, Any] | None = None,
    ) -> Outcome: ...


# the program flow's diagnostics of each kind of program: PAL's L<n> … M17, ISO's O<n> … M99
FLOW = {
    "L": FlowCodes(
        "PAL-E401", "PAL-E404", "PAL-E405", "PAL-E406", "PAL-E407", "PAL-E409", "PAL-E403", "PAL-E402"
    ),
    "O": FlowCodes(
        "ISO-E301", "ISO-E303", "ISO-E302", "PAL-E406", "PAL-E407", "ISO-E305", "ISO-E304", "ISO-W306", True
    ),
}

# the machine's state (a checkpoint keeps it): modal state, position, parameters (a copy, never mutated),
# what dropped blocks left unknown (FollowUps.unknown, never mutated)
MillState = tuple[ModalState, Vec3, dict[int, float], dict[str, int]]


class MillMachine(Machine):
    """Milling: `execute` runs one block on the state as values (pal_mill.execute_block)."""

    def __init__(
        self, table: CodeTable, execute: BlockExecutor, setup: RunSetup, readings: dict[Any, Any] | None
    ) -> None:
        self.table, self.execute, self.setup = table, execute, setup
        self.identity = (setup, table, execute)
        self.codes = FLOW[table.program_prefix]
        self.marks: set[int] = set()
        self.initial = self.state = switch_on_state(table)
        self.position = setup.start
        self.params: dict[int, float] = {}
        self.params_now: dict[int, float] = {}  # a copy of params as they are now (the checkpoints share it)
        self.follow = FollowUps()
        # the executor keeps its reading of blocks once the program first goes back (a call, a repeat, a
        # jump): until then every block runs once and keeping them would only cost
        self.readings, self.cache = readings, readings
        self.outcome: Outcome | None = None
        self.blocks: list[Block] = []  # the program's (units): the readings of other blocks are pruned

    def units(
        self, program: Program, library: dict[int, Program], diags: list[Diagnostic]
    ) -> tuple[Unit, dict[int, Unit], list[Unit]]:
        prefix = self.table.program_prefix
        main, subs = split_units(program, prefix)
        in_file = [main, *subs.values()]
        for number, prog in library.items():
            subs.setdefault(number, library_unit(number, prog, prefix))
        self.blocks = program.blocks
        return main, subs, in_file

    def step(self, block: Block, unit: Unit, program: str | None) -> Step:
        out = self.outcome = self.execute(
            self.setup, self.state, self.position, block, self.params, cache=self.cache
        )
        follow = self.follow
        note = ((unit.source, block.line), follow.unknown) if follow.unknown else None
        if block.assignments:
            self.params_now = dict(self.params)
        if follow.unknown or out.diagnostics:  # (else nothing is unknown before or after it)
            follow.ran(
                block,
                unit.source,
                out.diagnostics,
                out.executed,
                out.position != self.position,
                out.state.active("dimensions") != "G91",
            )
        flow, repeat = out.flow, out.repeat
        if self.cache is None and (flow is not None or repeat is not None or out.sub_end):
            self.cache = {}
        call: tuple[int | None, int | None, int | None, int, bool] | None = None
        jump = None
        if flow is not None:
            if flow[0] == "call":
                call = (flow[1], None, None, flow[2], False)
            else:
                jump = flow[1]
        elif repeat is not None:
            call = (None, repeat[0], repeat[1], repeat[2], True)
        commands = out.commands
        moves = 0
        for c in commands:  # (a loop, not sum() over a generator: this runs for every block)
            if type(c) is Planned:
                moves += 1
        return Step(
            commands, out.diagnostics, moves, call, jump, out.sub_end, out.ended, out.stopped, None, note
        )

    def commit(self) -> tuple[ModalState, Vec3]:
        out = self.outcome
        assert out is not None
        self.state, self.position = out.state, out.position
        return out.state, out.position

    def dropped(self, block: Block) -> None:
        self.follow.dropped(block)

    def skipped(self, block: Block) -> bool:
        return block.skip is not None and bool(self.setup.skip_blocks)

    def stamp(self, items: list[Any], source: str | None, stack: tuple[tuple[str | None, int], ...]) -> None:
        for c in items:
            if isinstance(c, Planned):
                c.move = c.move.with_fields(source=source, call_stack=stack)

    # -- checkpoints ---------------------------------------------------------------------------

    def snap(self) -> MillState:
        return (self.state, self.position, self.params_now, self.follow.unknown)

    def restore(self, snap: MillState) -> None:
        self.state, self.position, self.params_now, self.follow.unknown = snap
        self.params.clear()
        self.params.update(self.params_now)

    def shift(self, lm: LineMap, snap: MillState, done: dict[int, Any]) -> MillState:
        unknown = lm.unknown(snap[3])
        return snap if unknown is snap[3] else (snap[0], snap[1], snap[2], unknown)

    def shift_note(self, lm: LineMap, note: Any) -> Any:
        (source, line), unknown = note
        return (source, lm.line(line, source)), lm.unknown(unknown)

    def replay(self, note: Any) -> None:
        self.follow.at.setdefault(note[0], note[1])  # (first wins, as FollowUps.ran)

    # -- the end -------------------------------------------------------------------------------

    def commands(self, items: list[Any], diags: list[Diagnostic]) -> list[Any]:
        return finish(items, diags)

    def finish(self, result: Toolpath, states: list[ModalState | None], positions: list[Vec3 | None]) -> None:
        finish_toolpath(result, states, positions, self.setup.start, self.setup.answer_only)
        result.params = self.params
        result.final_position = self.position
        readings = self.readings
        if (
            readings is not None and len(readings) > 2 * len(self.blocks) + 256
        ):  # keep what this program can use
            alive = {id(b) for b in self.blocks}
            for key in [k for k in readings if k[0] not in alive]:
                del readings[key]

    def judge(self, diags: list[Diagnostic]) -> None:
        follow = self.follow
        follow.finish(diags)
