"""SINUMERIK 808D in ISO mode (milling): the code table.

Source: ../shared/spec/iso-808d-arcs.md and DECISIONS.md §13. Planes G17 (X-Y, centre I J),
G18 (Z-X, centre K I) and G19 (Y-Z, centre J K); G02/G03 with the end point and R (R+ at most
180°, R- the longer arc) or the centre offsets, which are always incremental from the start point.
An arc whose two end-point axes name another plane than the selected one lies in that plane. The
optional fifth linear axes U, V, W are not part of the trainer's 3-axis machine.
"""

from __future__ import annotations

from core.dialects import din
from core.dialects.codes import Code, CodeTable, Group

TABLE = CodeTable(
    codes={c.name: c for c in [
        *din.motion_codes(),
        *din.CODES,
        Code("G94", "feed_mode", "Vorschub in mm/min", "feed in mm/min"),
        Code("G95", "feed_mode", "Vorschub in mm/Umdrehung", "feed in mm per revolution"),
    ]},
    addresses={a.name: a for a in din.ADDRESSES},
    groups=(*din.GROUPS, Group("feed_mode", "Vorschubart", "feed mode", ("G94", "G95"), "G94")),
    always_allowed=frozenset({"F", "S", "M"}),
)
