"""The interpreter's state: one table of modal groups plus the technology values, and the set-up of a run.

A `ModalState` is immutable; a block that changes nothing modal shares its predecessor's
object, so keeping the state of every line costs one reference per line.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

from core.dialects.codes import CodeTable
from core.interpreter.frames import IDENTITY, Frame
from core.limits import DEFAULT_LIMITS, Limits
from core.toolpath import Vec3
from core.tools import DEFAULT_TOOLS, ToolTable
from core.values import value

if TYPE_CHECKING:
    from core.interpreter.pal_cycles import Definition


@dataclass(frozen=True, slots=True)
class DrillData:
    """What a drilling cycle (ISO G73–G89) keeps from block to block until G80: the initial level and the last
    programmed R, Z, Q and P, as written (in mm; under G91 R is the distance from the initial level and Z the
    distance from the R plane)."""

    initial: float  # the height of the drilling axis when the cycle was selected (program coordinates)
    z: float | None = None
    r: float | None = None
    q: float | None = None
    p: float | None = None  # dwell in ms


@value
class ModalState:
    """What is active: the code of each modal group (None: group not set) and the technology values."""

    codes: dict[str, str | None]  # group name → active code, e.g. "motion" → "G1"; never mutated
    feed: float = 0.0  # F
    speed: float = 0.0  # S
    tool: int | None = None  # tool in the spindle; None: none
    tc: int = 1
    tr: float = 0.0
    tl: float = 0.0
    pole: tuple[float, float] = (0.0, 0.0)  # of G10–G13: the last one programmed, at first the workpiece zero
    frame: Frame = IDENTITY  # how program coordinates map into the workpiece frame (G53–G59, G66)
    blend: float = 0.0  # Beckhoff: the I value of the last G301/G302, kept for the next one
    # under G41/G42: the unit end tangent (workpiece frame) of the last move in the plane, which a
    # departure G46/G48 continues; None: no such move since the compensation started
    tangent: tuple[float, float] | None = None
    arc_radius: float | None = None  # Beckhoff: the R of the last arc, kept for the next ones (modal radius)
    drill: DrillData | None = None  # ISO: the data of the active drilling cycle (None under G80)
    pal_cycle: Definition | None = (
        None  # PAL milling: the cycle defined last (G72–G75, G81–G87), which G76–G79 call
    )

    def active(self, group: str) -> str | None:
        """The active code of `group`, e.g. active("motion") == "G1"."""
        return self.codes.get(group)

    @property
    def spindle_on(self) -> bool:
        return self.codes.get("spindle") in ("M3", "M4")

    def to_json(self) -> dict[str, object]:
        return {
            "codes": dict(self.codes),
            "feed": self.feed,
            "speed": self.speed,
            "tool": self.tool,
            "tc": self.tc,
            "tr": self.tr,
            "tl": self.tl,
            "pole": list(self.pole),
            "frame": {
                "origin": list(self.frame.origin),
                "rotation": self.frame.rotation,
                "mirror_x": self.frame.mirror_x,
                "mirror_y": self.frame.mirror_y,
            },
        }


def switch_on_state(table: CodeTable) -> ModalState:
    """The state at program start (Einschaltzustand): each group's switch-on code, F0, S0, no tool."""
    return ModalState({g.name: g.switch_on for g in table.groups})


@dataclass(frozen=True, slots=True)
class RunSetup:
    """Everything a run needs besides the program: tools, limits, options, start position."""

    tools: ToolTable = DEFAULT_TOOLS
    limits: Limits = DEFAULT_LIMITS
    # True: blocks marked with "/" are skipped; False: they run; None: the dialect's default (PAL runs them,
    # TRAUB skips them: its "Ausblendsätze ein" key is off, DECISIONS §19)
    skip_blocks: bool | None = None
    start: Vec3 = (250.0, 150.0, 250.0)  # the tool-change position the PAL examples end at
    arc_tolerance: float = 0.01  # mm: end-point radius may differ this much from the start radius
    tool_changer: Literal["pickup"] = "pickup"
    # machine coordinates of the settable zero points G54…G57 (from the machine or exercise set-up)
    zero_offsets: tuple[tuple[str, Vec3], ...] = ()
    subprograms: tuple[tuple[int, str], ...] = ()  # program library: L number → program text
    max_call_depth: int = 8  # subprogram nesting (DECISIONS §7)
    # turning (TRAUB): the tool-change point of G24–G27 and the reference point of G28, machine coordinates
    # (X diameter, Z), SET UP-Bild 4 #1 (DECISIONS §21)
    tool_change_point: tuple[float, float] = (460.0, 585.0)
    # milling (ISO G28, G53): the reference point in the workpiece frame of G54, which is also the machine zero
    # of G53; None: the start position
    reference_point: Vec3 | None = None
    peck_retract: float = 1.0  # mm: the back-off of G73 and the clearance of G83 (machine data d)
    # True: the run makes only what an answer of the live editor shows — the commands, the diagnostics and the
    # final position; the state after every line and the lists of moves, dwells and tool changes stay empty
    answer_only: bool = False

    @property
    def reference(self) -> Vec3:
        return self.start if self.reference_point is None else self.reference_point

    def zero_offset(self, code: str) -> Vec3:
        return dict(self.zero_offsets).get(code, (0.0, 0.0, 0.0))
