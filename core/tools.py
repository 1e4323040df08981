"""Tools and the tool table: what sits in each magazine place T and its offset memories TC1…TC9."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

ToolKind = Literal["end_mill", "slot_drill", "ball_nose", "torus", "twist_drill", "spot_drill", "turning"]

KIND_NAMES_DE = {
    "end_mill": "Schaftfräser",
    "slot_drill": "Langlochfräser",
    "ball_nose": "Radiusfräser",
    "torus": "Eckradiusfräser",
    "twist_drill": "Spiralbohrer",
    "spot_drill": "NC-Anbohrer",
}
LATHE_KIND_NAMES_DE = {"turning": "Drehmeißel"}  # lathe tools: not in the milling simulation's default table
INSERTS = ("C", "D", "V", "groove", "thread")  # insert shapes of a turning tool (Tool.insert)


@dataclass(frozen=True, slots=True)
class ToolOffset:
    """Offset memory TC`tc` of a tool: the radius and length the control works with (mm)."""

    tc: int
    radius: float
    length: float


@dataclass(frozen=True, slots=True)
class Tool:
    number: int
    kind: ToolKind
    diameter: float  # mm
    name: str = ""
    # Shape, for the stock simulation; None means the default named in each property below.
    cutting_length: float | None = None  # mm from the tip; default 2 × diameter
    overall_length: float | None = None  # mm from the tip to the holder; default cutting length + 40
    shank_diameter: float | None = None  # mm; default the diameter
    centre_cutting: bool = True  # False: cannot plunge (Schaftfräser "nicht über Mitte schneidend")
    corner_radius: float = 0.0  # mm; torus; a ball-nose mill's is its radius
    point_angle: float = 0.0  # degrees; drills (118 twist drill, 90 spot drill)
    offsets: tuple[ToolOffset, ...] = ()  # offset memories TC1…TC9; missing ones: radius, overall length
    # Turning (TRAUB SET UP-Bild 2): the cutting edge's nose radius R_s in mm and quadrant P1…P4, where the
    # nose-radius centre lies relative to the theoretical tip (DECISIONS §16); 0: not given.
    nose_radius: float = 0.0
    quadrant: int = 0
    # The insert of a turning tool, for the turning simulation (core/sim/insert.py): "C" (80°), "D" (55°),
    # "V" (35°), "groove" (grooving insert of `width` B), "thread" (60° profile); "": C. `insert_angle`
    # overrides the letter's angle (degrees); `holder` is the holder's width, a boring bar's diameter (mm).
    insert: str = ""
    insert_angle: float = 0.0
    width: float = 0.0
    holder: float = 0.0

    @property
    def radius(self) -> float:
        return self.diameter / 2

    @property
    def flute_length(self) -> float:
        return self.cutting_length if self.cutting_length is not None else 2 * self.diameter

    @property
    def length(self) -> float:
        return self.overall_length if self.overall_length is not None else self.flute_length + 40

    @property
    def shank(self) -> float:
        return self.shank_diameter if self.shank_diameter is not None else self.diameter

    def offset(self, tc: int) -> ToolOffset:
        """Offset memory TC`tc`; one not in the table holds the tool's own radius and length."""
        for o in self.offsets:
            if o.tc == tc:
                return o
        return ToolOffset(tc, self.radius, self.length)


@dataclass(frozen=True)
class ToolTable:
    tools: dict[int, Tool]

    def get(self, number: int) -> Tool | None:
        return self.tools.get(number)

    def with_tool(self, tool: Tool) -> ToolTable:
        return ToolTable({**self.tools, tool.number: tool})


def _tool(
    number: int,
    kind: ToolKind,
    diameter: float,
    name: str,
    cutting: float,
    overall: float,
    centre: bool = True,
    corner: float = 0.0,
    angle: float = 0.0,
) -> Tool:
    return Tool(
        number,
        kind,
        diameter,
        name,
        cutting_length=cutting,
        overall_length=overall,
        shank_diameter=diameter,
        centre_cutting=centre,
        corner_radius=corner,
        point_angle=angle,
    )


def turning_tool(number: int, nose_radius: float, quadrant: int) -> Tool:
    """A lathe tool on turret station `number` with its nose radius (mm) and quadrant (1–4)."""
    return Tool(
        number,
        "turning",
        max(2 * nose_radius, 0.001),
        f"Drehmeißel R{nose_radius:g} P{quadrant}",
        nose_radius=nose_radius,
        quadrant=quadrant,
    )


# Free practice (and every run that names no other table): the tools of the PAL examples (T1, T2,
# T4) and one of every other kind. core/sim/default_tools.yaml is the same table as a file.
DEFAULT_TOOLS = ToolTable(
    {
        t.number: t
        for t in (
            _tool(1, "end_mill", 25.0, "Schaftfräser Ø25", 40.0, 100.0),
            _tool(2, "slot_drill", 6.0, "Langlochfräser Ø6", 13.0, 57.0),
            _tool(3, "ball_nose", 10.0, "Radiusfräser Ø10", 22.0, 72.0),
            _tool(4, "end_mill", 20.0, "Schaftfräser Ø20", 38.0, 104.0),
            _tool(5, "torus", 16.0, "Eckradiusfräser Ø16 R2", 30.0, 90.0, corner=2.0),
            _tool(6, "twist_drill", 8.5, "Spiralbohrer Ø8,5 118°", 75.0, 117.0, angle=118.0),
            _tool(7, "spot_drill", 10.0, "NC-Anbohrer Ø10 90°", 20.0, 80.0, angle=90.0),
            _tool(
                8, "end_mill", 16.0, "Schaftfräser Ø16, nicht über Mitte schneidend", 32.0, 92.0, centre=False
            ),
        )
    }
)
