"""Beckhoff TwinCAT CNC (DIN 66025 milling): the code table, with chamfers and roundings G301/G302.

Source: ../shared/spec/beckhoff-chamfer-round.md and DECISIONS.md §14. `G301 I…` (chamfer) and
`G302 I…` (rounding) in a block of their own act on the corner between the motion blocks before
and after them; I is kept for the next G301/G302 and must not be 0 the first time. The extended
forms `G301=…`, `G302=…`, `#CHR=…` (chamfer width), `#CHF=…` (chamfer length) and `#RND=…`
(radius) go into the first of the two motion blocks and are not kept. `#FRC=…` is the feed in the
inserted element only. The element lies in the plane of the second motion block.
"""

from __future__ import annotations

from core.dialects import din
from core.dialects.codes import Address, Code, CodeTable

TRANSITIONS = frozenset({"G301", "G302", "#CHR", "#CHF", "#RND", "#FRC"})
VALUED_CODES = frozenset({"G301", "G302"})  # written G301=20 in a motion block

TABLE = CodeTable(
    codes={c.name: c for c in [
        *din.motion_codes(TRANSITIONS),
        *din.CODES,
        Code("G301", None, "Fase zwischen zwei Verfahrsätzen einfügen (Breite I)",
             "insert a chamfer between two motion blocks (width I)", words=frozenset({"I", "#FRC"}),
             owns_block=True, example="N30 G301 I20", rule_de="I wird gespeichert und gilt für die nächsten G301/G302",
             rule_en="I is kept for the next G301/G302"),
        Code("G302", None, "Radius zwischen zwei Verfahrsätzen einfügen (Radius I)",
             "insert a rounding between two motion blocks (radius I)", words=frozenset({"I", "#FRC"}),
             owns_block=True, example="N30 G302 I5", rule_de="I wird gespeichert und gilt für die nächsten G301/G302",
             rule_en="I is kept for the next G301/G302"),
    ]},
    addresses={a.name: a for a in [
        *(a for a in din.ADDRESSES if a.name != "I"),
        Address("I", "Kreismittelpunkt X (inkremental); bei G301/G302 Fasenbreite bzw. Radius",
                "centre X (incremental); with G301/G302 chamfer width or radius", unit="mm"),
        Address("G301", "Fase mit Breite (G301=…, nicht haltend)", "chamfer of this width (G301=…, not kept)", unit="mm"),
        Address("G302", "Radius (G302=…, nicht haltend)", "rounding of this radius (G302=…, not kept)", unit="mm"),
        Address("#CHR", "Fasenbreite", "chamfer width", unit="mm"),
        Address("#CHF", "Fasenlänge", "chamfer length", unit="mm"),
        Address("#RND", "Radius", "rounding radius", unit="mm"),
        Address("#FRC", "Vorschub im eingefügten Element", "feed in the inserted element", unit="mm/min"),
    ]},
    groups=din.GROUPS,
    always_allowed=frozenset({"F", "S", "M"}),
)
