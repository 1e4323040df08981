"""Tools and the tool table: what sits in each magazine place T and its offset memories TC1…TC9."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

ToolKind = Literal["end_mill", "slot_drill"]

KIND_NAMES_DE = {"end_mill": "Schaftfräser", "slot_drill": "Langlochfräser"}


@dataclass(frozen=True, slots=True)
class Tool:
    number: int
    kind: ToolKind
    diameter: float  # mm
    name: str = ""

    @property
    def radius(self) -> float:
        return self.diameter / 2


@dataclass(frozen=True)
class ToolTable:
    tools: dict[int, Tool]

    def get(self, number: int) -> Tool | None:
        return self.tools.get(number)

    def with_tool(self, tool: Tool) -> ToolTable:
        return ToolTable({**self.tools, tool.number: tool})


# The tools of the seed examples (free practice uses this table).
DEFAULT_TOOLS = ToolTable(
    {
        1: Tool(1, "end_mill", 25.0, "Schaftfräser Ø25"),
        2: Tool(2, "slot_drill", 6.0, "Langlochfräser Ø6"),
        4: Tool(4, "end_mill", 20.0, "Schaftfräser Ø20"),
    }
)
