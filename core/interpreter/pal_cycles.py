"""PAL milling cycles: the definitions G72–G75, G81–G87 and the calls G76–G79 expanded into canonical moves.

Source: ../shared/spec/pal-cycles.md, a specification *reconstructed* from the PAL milling programming key as
it is taught (the seeds stop before the cycles). Every choice of low certainty (a default, the meaning of a
word where teaching material differs) is a row of `RECONSTRUCTED` below, the one place to correct it; the
code reads its values from there and docs/pal-milling.md lists the rows.

A cycle block **defines** the cycle (stored in `ModalState.pal_cycle`, nothing moves); a call runs the
definition at one point (G79 cartesian, G78 polar) or at several (G76 on a line, G77 on a pitch circle). At
each point: rapid up to the retraction height if the tool is below it, rapid in the plane to the cycle's entry
point, rapid down to the safety height (surface + V), the cycle, rapid up to the retraction height (W when the
definition gives it, else surface + V). Everything here is in program coordinates; the caller maps the moves
into the workpiece frame. Each move carries `cycle = (code, step, steps)` — the levels of a pocket or slot,
the pecks of a deep hole, one step otherwise — the calling block's span and `cycle_definition`, the line of
the defining block.

Pockets and slots are cut level by level (levels of at most D, spread evenly over the depth); on each level
the tool plunges at the start of the shape's core line (its medial axis: the centre point of a circular
pocket, the centre line of a slot or of a rectangle), runs along the core and then on rings at growing
distance from the core, the last one on the wall (contour-parallel, step-over DB % of the tool diameter),
and goes back along the core for the next level. Rings are exact offsets of the core, so every point between
two rings lies within half a step-over of one of them.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

from core.diagnostics import Diagnostic, diag
from core.interpreter.cycle_path import EPS, CyclePath
from core.interpreter.state import ModalState, RunSetup
from core.syntax.blocks import Span, Word
from core.toolpath import Dwell, Move, Vec3

Pt = tuple[float, float]


@dataclass(frozen=True, slots=True)
class Choice:
    """One reconstructed choice: its value, what it means (German, English) and its certainty (L or M)."""

    value: float
    de: str
    en: str
    certainty: Literal["L", "M"] = "L"


# Every choice of low (and the medium defaults of) certainty, in one place: correct a row here and the cycles,
# the hover help and the docs follow.
RECONSTRUCTED: dict[str, Choice] = {
    "surface": Choice(0.0, "Aufruf ohne Z: Werkstückoberfläche Z 0", "a call without Z: surface Z 0", "M"),
    "W": Choice(
        0.0,
        "W unter der Sicherheitshöhe: Rückzug auf Oberfläche + V",
        "W below the safety height: retraction to surface + V",
    ),
    "VB": Choice(
        1.0,
        "G82/G83: Rückzug VB nach jedem Bohrschritt 1 mm",
        "G82/G83: retraction VB after each step 1 mm",
        "M",
    ),
    "DR": Choice(
        0.0,
        "G82/G83: Verringerung DR je Bohrschritt 0 mm (Schritt k ≥ 2: D − (k − 1) · DR)",
        "G82/G83: reduction DR per step 0 mm (step k ≥ 2: D − (k − 1) · DR)",
    ),
    "DM": Choice(
        1.0,
        "G82/G83: kleinster Bohrschritt DM 1 mm, höchstens D",
        "G82/G83: smallest step DM 1 mm, at most D",
    ),
    "G86_side": Choice(
        -1.0,
        "G86: Abheben um DR in −X-Richtung (Standard DR 0)",
        "G86: retraction by DR towards −X (default DR 0)",
    ),
    "G87_start": Choice(
        0.0,
        "G87: die Schraubenlinie beginnt in Sicherheitshöhe, gegen den Uhrzeigersinn",
        "G87: the helix starts at the safety height, counter-clockwise",
    ),
    "G77_spacing": Choice(
        360.0,
        "G77 ohne AI und AP: O Punkte gleichmäßig auf dem Vollkreis",
        "G77 without AI and AP: O points evenly on the full circle",
    ),
    "EP": Choice(
        0,
        "EP0: Bezugspunkt Mitte (Standard); EP1: linke untere Ecke (G72) bzw. Mittelpunkt des "
        "Anfangsbogens (G74, G75)",
        "EP0: reference point centre (default); EP1: lower left corner (G72) or centre of the start arc "
        "(G74, G75)",
    ),
    "DB": Choice(
        80.0, "DB: Bahnüberdeckung 80 % des Fräserdurchmessers", "DB: path overlap 80 % of the tool diameter"
    ),
    "H": Choice(
        1,
        "H1 Schruppen (Standard, lässt AK/AL stehen), H4 Schlichten (Boden in einer Ebene, Wände in "
        "Ebenen von D), H14 Schruppen und Schlichten",
        "H1 roughing (default, leaves AK/AL), H4 finishing (bottom in one level, walls in levels of D), "
        "H14 roughing then finishing",
    ),
    "O": Choice(
        1,
        "O1 senkrechtes Eintauchen (Standard), O2 Eintauchen auf einer Schraubenlinie (eine Umdrehung je "
        "Ebene)",
        "O1 vertical plunge (default), O2 helical plunge (one turn per level)",
    ),
    "O2_radius": Choice(
        0.5,
        "O2: Radius der Schraubenlinie das 0,5-Fache des Fräserradius",
        "O2: helix radius 0.5 times the tool radius",
    ),
    "Q": Choice(
        1,
        "Q1 Gleichlauf (Standard, gegen den Uhrzeigersinn um die Tasche), Q2 Gegenlauf",
        "Q1 climb milling (default, counter-clockwise round the pocket), Q2 conventional",
    ),
    "RZ": Choice(
        0.0,
        "G73 mit RZ (Zapfenradius): Zapfenfräsen, noch nicht unterstützt",
        "G73 with RZ (boss radius): boss milling, not supported yet",
    ),
    "E": Choice(
        0.0, "E (Eintauchvorschub): Standard der Vorschub F", "E (plunge feed): default the feed F", "M"
    ),
    "RN": Choice(
        0.0,
        "RN (Eckenradius G72): Standard der Werkzeugradius; kleiner: Warnung, Werkzeugradius",
        "RN (corner radius G72): default the tool radius; smaller: a warning, the tool radius",
        "M",
    ),
}

# the pitches of ISO metric threads, coarse (DIN 13-1) and fine: G84 warns on any other F
STANDARD_PITCHES = frozenset(
    {
        0.2,
        0.25,
        0.3,
        0.35,
        0.4,
        0.45,
        0.5,
        0.6,
        0.7,
        0.75,
        0.8,
        1.0,
        1.25,
        1.5,
        1.75,
        2.0,
        2.5,
        3.0,
        3.5,
        4.0,
        4.5,
        5.0,
        5.5,
        6.0,
    }
)

DRILLING = ("G81", "G82", "G83", "G84", "G85", "G86", "G87")
MILLING = ("G72", "G73", "G74", "G75")
DEFINITIONS = frozenset(DRILLING + MILLING)
CALLS = frozenset({"G76", "G77", "G78", "G79"})
# the values each choice word may take
_CHOICES = {
    "H": ((1, 4, 14), "1, 4, 14"),
    "O": ((1, 2), "1, 2"),
    "Q": ((1, 2), "1, 2"),
    "EP": ((0, 1), "0, 1"),
}


@dataclass(frozen=True, slots=True)
class Definition:
    """A cycle as its block defined it: the code, its words (values as written) and its technology."""

    code: str
    values: tuple[tuple[str, float], ...]
    line: int
    feed: float | None = None  # F of the defining block (G84: the pitch)
    direction: Literal["cw", "ccw"] | None = None  # G84: M3 right-hand, M4 left-hand thread

    def get(self, address: str, default: float | None = None) -> float | None:
        return next((v for a, v in self.values if a == address), default)

    def has(self, address: str) -> bool:
        return any(a == address for a, _ in self.values)


def _de(value: float) -> str:
    """A number for a German text: decimal comma, no trailing zeros."""
    text = f"{value:.4f}".rstrip("0").rstrip(".")
    return ("0" if text == "-0" else text).replace(".", ",")


def _en(value: float) -> str:
    return _de(value).replace(",", ".")


def check_block(
    name: str,
    span: Span,
    words: dict[str, list[Word]],
    values: dict[str, float],
    state: ModalState,
    ms: list[str],
    d: list[Diagnostic],
) -> None:
    """What the code table cannot say about a cycle or call block: the compensation, the choice words, the
    allowances, the sign of ZI, counts."""
    compensation = state.codes.get("compensation")
    if compensation in ("G41", "G42"):
        d.append(diag("PAL-E608", span, command=name, compensation=compensation))
    for a, (allowed, text) in _CHOICES.items():
        if a in values and name in DEFINITIONS and values[a] not in allowed:
            d.append(
                diag(
                    "PAL-E611",
                    words[a][0].span,
                    address=a,
                    raw=words[a][0].raw,
                    command=name,
                    allowed=text,
                    allowed_en=text,
                )
            )
    if "DB" in values and not 0 < values["DB"] <= 100:
        d.append(
            diag(
                "PAL-E611",
                words["DB"][0].span,
                address="DB",
                raw=words["DB"][0].raw,
                command=name,
                allowed="größer 0 bis 100 (%)",
                allowed_en="above 0 up to 100 (%)",
            )
        )
    for a in ("AK", "AL"):
        if a in values and values[a] < 0:
            d.append(diag("PAL-E604", words[a][0].span, address=a, raw=words[a][0].raw))
    if name in DEFINITIONS and "ZI" in values and values["ZI"] >= 0:
        d.append(
            diag(
                "PAL-E603",
                words["ZI"][0].span,
                command=name,
                bottom=_de(values["ZI"]),
                surface="0",
                bottom_en=_en(values["ZI"]),
                surface_en="0",
            )
        )
    for a in ("R", "RP", "BP", "LP", "DA", "DM", "RN"):
        if a in values and values[a] <= 0:
            d.append(diag("PAL-E213", words[a][0].span, address=a, raw=words[a][0].raw))
    for a in ("V", "VB", "DR", "U"):
        if a in values and values[a] < 0:
            d.append(diag("PAL-E109", words[a][0].span, address=a, raw=words[a][0].raw))
    if name == "G84":
        if not {"M3", "M4", "M13", "M14"} & set(ms):
            d.append(diag("PAL-E102", span, address="M3/M4", command=name))
        if "F" not in values:
            d.append(diag("PAL-E102", span, address="F (Steigung)", command=name))
        elif round(values["F"], 4) not in STANDARD_PITCHES:
            d.append(diag("PAL-W607", words["F"][0].span, pitch=words["F"][0].raw))
    if name in ("G76", "G77") and "O" in values and values["O"] < 1:
        d.append(
            diag(
                "PAL-E611",
                words["O"][0].span,
                address="O",
                raw=words["O"][0].raw,
                command=name,
                allowed="Anzahl der Punkte, mindestens 1",
                allowed_en="the number of points, at least 1",
            )
        )


def define(name: str, values: dict[str, float], line: int, state: ModalState, ms: list[str]) -> Definition:
    """The definition a cycle block stores (its words checked before)."""
    direction: Literal["cw", "ccw"] | None = None
    if name == "G84":
        direction = "ccw" if "M4" in ms or "M14" in ms else "cw" if "M3" in ms or "M13" in ms else None
    kept = tuple(sorted((a, v) for a, v in values.items() if a not in ("F", "S", "M")))
    return Definition(name, kept, line, values.get("F"), direction)


def _points(
    name: str,
    here: Vec3,
    values: dict[str, float],
    incremental: bool,
    span: Span,
    d: list[Diagnostic],
    limit: int,
) -> list[tuple[float, float, float]] | None:
    """The call's points (x, y, surface z) in program coordinates."""
    if "Z" in values:
        surface = values["Z"]
    elif "ZA" in values:
        surface = values["ZA"]
    elif "ZI" in values:
        surface = here[2] + values["ZI"]
    else:
        surface = RECONSTRUCTED["surface"].value
    if name == "G79" or name == "G76":
        x, y = here[0], here[1]
        for i, (plain, inc, absolute) in enumerate((("X", "XI", "XA"), ("Y", "YI", "YA"))):
            if plain in values:
                v = here[i] + values[plain] if incremental else values[plain]
            elif inc in values:
                v = here[i] + values[inc]
            elif absolute in values:
                v = values[absolute]
            else:
                continue
            x, y = (v, y) if i == 0 else (x, v)
        if name == "G79":
            return [(x, y, surface)]
        count = int(values["O"])
        if count > limit:
            d.append(diag("PAL-E610", span, command=name, count=count, limit=limit))
            return None
        a = math.radians(values.get("AS", 0.0))
        step = values["D"]
        return [(x + k * step * math.cos(a), y + k * step * math.sin(a), surface) for k in range(count)]
    cx = values["IA"] if "IA" in values else here[0] + values.get("I", 0.0)
    cy = values["JA"] if "JA" in values else here[1] + values.get("J", 0.0)
    if name == "G78":
        a = math.radians(values["AP"])
        return [(cx + values["RP"] * math.cos(a), cy + values["RP"] * math.sin(a), surface)]
    count = int(values["O"])
    if count > limit:
        d.append(diag("PAL-E610", span, command=name, count=count, limit=limit))
        return None
    first = values.get("AN", 0.0)
    if "AI" in values:
        step = values["AI"]
    elif "AP" in values:
        step = (values["AP"] - first) / (count - 1) if count > 1 else 0.0
    else:
        step = RECONSTRUCTED["G77_spacing"].value / count
    r = values["R"]
    return [
        (
            cx + r * math.cos(math.radians(first + k * step)),
            cy + r * math.sin(math.radians(first + k * step)),
            surface,
        )
        for k in range(count)
    ]


class _Path(CyclePath):
    """Collects the moves of one call (program coordinates), with arcs and helices."""

    def __init__(self, code: str, template: Move, span: Span, line: int, start: Vec3) -> None:
        super().__init__(code, template, span, start, definition=line)

    def arc(self, to: Vec3, centre: Pt, ccw: bool, feed: float | None = None, full: bool = False) -> None:
        """An arc (a helix when Z changes) about `centre` to `to`; `full`: a whole turn back to the same point."""
        s = self.pos
        r = math.dist((s[0], s[1]), centre)
        if r < 1e-6:
            self.go("feed", to, feed=feed)
            return
        a0 = math.atan2(s[1] - centre[1], s[0] - centre[0])
        a1 = math.atan2(to[1] - centre[1], to[0] - centre[0])
        sweep = math.degrees(a1 - a0) if ccw else math.degrees(a0 - a1)
        sweep %= 360.0
        if full or sweep < 1e-7:
            sweep = 360.0 if full or math.dist((s[0], s[1]), (to[0], to[1])) < 1e-7 else sweep
        if sweep < 1e-7:
            return
        self.go(
            "arc",
            to,
            feed=feed,
            center=(centre[0], centre[1], s[2]),
            direction="ccw" if ccw else "cw",
            radius=r,
            angle=sweep,
        )


@dataclass(frozen=True, slots=True)
class Seg:
    """A piece of a path in the plane from the previous end: a line, or an arc about `centre`."""

    end: Pt
    centre: Pt | None = None
    ccw: bool = True


@dataclass(frozen=True, slots=True)
class Shape:
    """A pocket or slot in its own frame (origin: its reference point): where the tool plunges, its core line
    (medial axis), and the ring about the core at a distance t."""

    kind: str  # "rect", "circle", "slot", "arc"
    reach: float  # the largest distance from the core the tool centre may go (wall − tool radius − AK)
    a: float = 0.0  # rect: half the longer side's core length; slot: half its core length
    rc: float = 0.0  # rect: corner radius of the tool centre's outermost ring
    radius: float = 0.0  # arc slot: radius of its centre line
    t0: float = 0.0  # arc slot: start angle, radians
    t1: float = 0.0  # arc slot: end angle, radians (> t0)

    def _at(self, angle: float, r: float) -> Pt:
        return (r * math.cos(angle), r * math.sin(angle))

    def core_start(self) -> Pt:
        if self.kind == "arc":
            return self._at(self.t0, self.radius)
        return (-self.a, 0.0)

    def core(self) -> list[Seg]:
        if self.kind == "arc":
            return [Seg(self._at(self.t1, self.radius), (0.0, 0.0), True)]
        return [Seg((self.a, 0.0))] if self.a > EPS else []

    def core_end(self) -> Pt:
        segs = self.core()
        return segs[-1].end if segs else self.core_start()

    def ring(self, t: float) -> tuple[Pt, list[Seg]]:
        """The closed ring at distance t from the core, counter-clockwise, and its start (straight out from
        the core's end)."""
        if self.kind == "arc":
            p0, p1 = self._at(self.t0, self.radius), self._at(self.t1, self.radius)
            start = self._at(self.t1, self.radius + t)
            inner = self.radius - t
            return start, [
                Seg(self._at(self.t1, inner), p1, True),
                Seg(self._at(self.t0, inner), (0.0, 0.0), False)
                if inner > 1e-6
                else Seg(self._at(self.t0, inner)),
                Seg(self._at(self.t0, self.radius + t), p0, True),
                Seg(start, (0.0, 0.0), True),
            ]
        a = self.a
        if self.kind in ("circle", "slot"):
            start = (a + t, 0.0)
            return start, [
                s
                for s in (
                    Seg((a, t), (a, 0.0)),
                    Seg((-a, t)) if a > EPS else None,
                    Seg((-a, -t), (-a, 0.0)),
                    Seg((a, -t)) if a > EPS else None,
                    Seg(start, (a, 0.0)),
                )
                if s is not None
            ]
        # rect: half sizes (a + t, t), corner radius of the inward offset of the outermost ring
        hx, hy, r = a + t, t, max(self.rc - (self.reach - t), 0.0)
        start = (hx, 0.0)
        segs: list[Seg] = []
        corners = (((hx, hy), (1, 1)), ((-hx, hy), (-1, 1)), ((-hx, -hy), (-1, -1)), ((hx, -hy), (1, -1)))
        for (cx, cy), (sx, sy) in corners:
            # along the side to the corner's arc, then round the corner (counter-clockwise)
            if sx == sy:
                before, after = (cx, cy - sy * r), (cx - sx * r, cy)
            else:
                before, after = (cx - sx * r, cy), (cx, cy - sy * r)
            segs.append(Seg(before))
            if r > 1e-9:
                segs.append(Seg(after, (cx - sx * r, cy - sy * r), True))
        segs.append(Seg(start))
        return start, segs


def _reversed(start: Pt, segs: list[Seg]) -> list[Seg]:
    """The same path backwards (from its end to `start`)."""
    points = [start] + [s.end for s in segs]
    return [Seg(points[i], segs[i].centre, not segs[i].ccw) for i in reversed(range(len(segs)))]


def _offsets(reach: float, step: float) -> list[float]:
    """The rings' distances from the core, innermost first, the last one `reach`, at most `step` apart."""
    if reach <= 1e-6:
        return []
    n = max(1, math.ceil(reach / step - 1e-9))
    return [reach - k * step for k in reversed(range(n))]


def _count(length: float, step: float, least: float = 1e-9) -> int:
    """How many pieces of at most `step` make `length` (0 for nothing), without making them."""
    return 0 if length <= least else max(1, math.ceil(length / step - 1e-9))


def _levels(top: float, bottom: float, infeed: float) -> list[float]:
    """Heights of the levels from `top` down to `bottom`, at most `infeed` apart, spread evenly."""
    depth = top - bottom
    if depth <= 1e-9:
        return []
    n = max(1, math.ceil(depth / infeed - 1e-9))
    return [top - depth * (k + 1) / n for k in range(n)]


def _tool_radius(setup: RunSetup, state: ModalState) -> float:
    tool = setup.tools.get(state.tool) if state.tool is not None else None
    return tool.offset(state.tc).radius + state.tr if tool is not None else 0.0


def call(
    setup: RunSetup,
    state: ModalState,
    here: Vec3,
    name: str,
    values: dict[str, float],
    template: Move,
    span: Span,
    d: list[Diagnostic],
) -> tuple[list[Move | Dwell], Vec3] | None:
    """The moves of a call block from `here` (program coordinates) and where the tool ends; None after an error."""
    definition = state.pal_cycle
    if definition is None:
        d.append(diag("PAL-E601", span, command=name))
        return None
    limit = setup.limits.max_cycle_passes
    points = _points(name, here, values, state.active("dimensions") == "G91", span, d, limit)
    if points is None:
        return None
    code = definition.code
    rt = _tool_radius(setup, state)
    feed = definition.feed if definition.feed is not None and code != "G84" else template.feed
    template = dataclasses.replace(template, feed=feed)
    v = definition.get("V", 0.0) or 0.0
    w = definition.get("W")
    rotation = values.get("AR", 0.0)
    plan = _Planner(definition, template, span, rt, limit, state, d)
    if not plan.check(points[0][2]):
        return None
    if len(points) * plan.passes > setup.limits.max_moves:  # (each pass makes a move at least)
        d.append(diag("PAL-E017", span, limit=setup.limits.max_moves))
        return None
    path = _Path(code, template, span, definition.line, here)
    for k, (x, y, surface) in enumerate(points, 1):
        path.point = (k, len(points))
        safety = surface + v
        retract = max(w, safety) if w is not None else safety  # (RECONSTRUCTED["W"])
        if path.pos[2] < retract - EPS:
            path.go("rapid", (path.pos[0], path.pos[1], retract))
        entry = plan.entry(x, y, rotation)
        first = len(path.items)
        path.step = path.steps = 1
        path.go("rapid", (entry[0], entry[1], path.pos[2]))
        path.go("rapid", (entry[0], entry[1], safety))
        if not plan.run(path, x, y, surface, rotation):
            return None
        path.go("rapid", (path.pos[0], path.pos[1], retract))
        for i in range(
            first, len(path.items)
        ):  # the positioning belongs to the first step, as the steps now know
            item = path.items[i]
            if isinstance(item, Move) and item.cycle is not None and item.cycle[2] != path.steps:
                path.items[i] = dataclasses.replace(item, cycle=(code, item.cycle[1], path.steps))
    return path.items, path.pos


class _Planner:
    """The motion of one definition at one point."""

    def __init__(
        self,
        definition: Definition,
        template: Move,
        span: Span,
        rt: float,
        limit: int,
        state: ModalState,
        d: list[Diagnostic],
    ) -> None:
        self.df, self.template, self.span, self.rt, self.limit, self.state, self.d = (
            definition,
            template,
            span,
            rt,
            limit,
            state,
            d,
        )
        self.shape: Shape | None = None
        self.passes = (
            1  # at one point: the levels × rings of a pocket, the steps of a deep hole, the turns of G87
        )
        self.depths: list[float] = []  # G82/G83: the depths the steps reach, from the surface
        self.nominal: Shape | None = None  # the shape to size (AK 0): finishing
        self.swap = False  # the shape's long axis is X: a pocket taller than wide is turned by 90°
        self.step_over = 1.0

    def value(self, address: str, default: float = 0.0) -> float:
        got = self.df.get(address)
        return default if got is None else got

    def bottom(self, surface: float) -> float:
        zi = self.df.get("ZI")
        return surface + zi if zi is not None else self.value("ZA")

    def check(self, surface: float) -> bool:
        """The checks that need the tool and the surface; builds the shape of a pocket or slot."""
        df, d, span, code = self.df, self.d, self.span, self.df.code
        bottom = self.bottom(surface)
        if bottom >= surface - EPS:
            d.append(
                diag(
                    "PAL-E603",
                    span,
                    command=code,
                    bottom=_de(bottom),
                    surface=_de(surface),
                    bottom_en=_en(bottom),
                    surface_en=_en(surface),
                )
            )
            return False
        depth = surface - bottom
        if code == "G87":
            if 2 * self.rt >= 2 * self.value("R") - EPS:
                return self._too_large("die Bohrung Ø", "the hole Ø", 2 * self.value("R"))
            turns = (depth + self.value("V")) / self.value("D")
            self.passes = math.ceil(turns) + 1
            if turns + 2 > self.limit:
                d.append(diag("PAL-E610", span, command=code, count=self.passes, limit=self.limit))
                return False
            return True
        if code in ("G82", "G83"):
            reduce = self.value("DR", RECONSTRUCTED["DR"].value)
            depths = steps(depth, self.value("D"), df.get("DA"), reduce, df.get("DM"), self.limit)
            if depths is None:
                d.append(diag("PAL-E610", span, command=code, count=f"> {self.limit}", limit=self.limit))
                return False
            self.depths, self.passes = depths, len(depths)
        if code in DRILLING:
            return True
        ak, al = self.value("AK"), self.value("AL")
        if al >= depth - EPS and self.df.has("AL"):
            d.append(
                diag(
                    "PAL-E605",
                    span,
                    command=code,
                    address="AL",
                    value=_de(al),
                    value_en=_en(al),
                    what="die Tiefe",
                    what_en="the depth",
                    limit=_de(depth),
                    limit_en=_en(depth),
                )
            )
            return False
        rt = self.rt
        if code == "G72":
            lp, bp = self.value("LP"), self.value("BP")
            rn = self.value("RN", rt) if df.has("RN") else rt
            if rn < rt - EPS:
                raw = _en(rn)
                d.append(diag("PAL-W609", span, raw=raw, radius=_de(rt), radius_en=_en(rt)))
                rn = rt
            small = min(lp, bp)
            if 2 * rt > small + EPS:
                return self._too_large(
                    "die Tasche mit der kleineren Seite ", "the pocket with the shorter side ", small
                )
            if rn > small / 2 + EPS:
                d.append(
                    diag(
                        "PAL-E612",
                        span,
                        command=code,
                        reason=f"der Eckenradius RN {_de(rn)} mm ist größer als die halbe Taschenbreite",
                        reason_en=f"the corner radius RN {_en(rn)} mm is larger than half the pocket's width",
                    )
                )
                return False
            reach = small / 2 - rt - ak
            if reach < -EPS:
                return self._allowance(ak, small / 2 - rt)
            a = abs(lp - bp) / 2
            self.shape = Shape("rect", max(reach, 0.0), a=a, rc=max(rn - rt - ak, 0.0))
            self.nominal = Shape("rect", small / 2 - rt, a=a, rc=rn - rt)
            self.swap = bp > lp
        elif code == "G73":
            r = self.value("R")
            if rt > r + EPS:
                return self._too_large("die Kreistasche Ø", "the circular pocket Ø", 2 * r)
            reach = r - rt - ak
            if reach < -EPS:
                return self._allowance(ak, r - rt)
            self.shape = Shape("circle", max(reach, 0.0))
            self.nominal = Shape("circle", r - rt)
        elif code == "G74":
            lp, bp = self.value("LP"), self.value("BP")
            if lp < bp - EPS:
                d.append(
                    diag(
                        "PAL-E612",
                        span,
                        command=code,
                        reason=f"die Länge LP {_de(lp)} mm ist kleiner als die Breite BP {_de(bp)} mm",
                        reason_en=f"the length LP {_en(lp)} mm is less than the width BP {_en(bp)} mm",
                    )
                )
                return False
            if 2 * rt > bp + EPS:
                return self._too_large("die Nut der Breite ", "the slot of width ", bp)
            reach = bp / 2 - rt - ak
            if reach < -EPS:
                return self._allowance(ak, bp / 2 - rt)
            self.shape = Shape("slot", max(reach, 0.0), a=max(lp - bp, 0.0) / 2)
            self.nominal = Shape("slot", bp / 2 - rt, a=max(lp - bp, 0.0) / 2)
        else:  # G75
            bp, rp = self.value("BP"), self.value("RP")
            an = self.value("AN")
            sweep = self.value("AO") if df.has("AO") else self.value("AP") - an
            if rp < bp / 2 - EPS or abs(sweep) < 1e-6 or abs(sweep) >= 360 - 1e-6:
                reason = (
                    (
                        "der Radius RP ist kleiner als die halbe Nutbreite",
                        "the radius RP is less than half the slot's width",
                    )
                    if rp < bp / 2 - EPS
                    else (
                        "der Öffnungswinkel muss zwischen 0° und 360° liegen",
                        "the opening angle must lie between 0° and 360°",
                    )
                )
                d.append(diag("PAL-E612", span, command=code, reason=reason[0], reason_en=reason[1]))
                return False
            if 2 * rt > bp + EPS:
                return self._too_large("die Nut der Breite ", "the slot of width ", bp)
            reach = bp / 2 - rt - ak
            if reach < -EPS:
                return self._allowance(ak, bp / 2 - rt)
            t0, t1 = sorted((math.radians(an), math.radians(an + sweep)))
            self.shape = Shape("arc", max(reach, 0.0), radius=rp, t0=t0, t1=t1)
            self.nominal = Shape("arc", bp / 2 - rt, radius=rp, t0=t0, t1=t1)
        step = max(self.value("DB", RECONSTRUCTED["DB"].value) / 100 * 2 * rt, 1e-3)
        rings = _count(self.shape.reach, step, 1e-6) + 1
        h, infeed = int(self.value("H", RECONSTRUCTED["H"].value)), self.value("D")
        levels = (_count(depth - al, infeed) if h in (1, 14) else 0) + (
            _count(depth, infeed) if h in (4, 14) else 0
        )
        self.passes = rings * max(levels, 1)
        if rings * max(levels, 1) > self.limit:
            d.append(diag("PAL-E610", span, command=code, count=rings * levels, limit=self.limit))
            return False
        self.step_over = step
        return True

    def _too_large(self, what: str, what_en: str, size: float) -> bool:
        tool = self.state.tool
        self.d.append(
            diag(
                "PAL-E602",
                self.span,
                command=self.df.code,
                tool=tool,
                tool_d=_de(2 * self.rt),
                tool_d_en=_en(2 * self.rt),
                what=what,
                what_en=what_en,
                size=_de(size),
                size_en=_en(size),
            )
        )
        return False

    def _allowance(self, ak: float, most: float) -> bool:
        self.d.append(
            diag(
                "PAL-E605",
                self.span,
                command=self.df.code,
                address="AK",
                value=_de(ak),
                value_en=_en(ak),
                what="die halbe Breite abzüglich des Fräserradius",
                what_en="half the width less the tool radius",
                limit=_de(max(most, 0.0)),
                limit_en=_en(max(most, 0.0)),
            )
        )
        return False

    def _plan_levels(self, surface: float, bottom: float) -> list[tuple[float, str]]:
        """(height, what) per level: "rough" (core and every ring, leaving AK and AL), "wall" (the wall only,
        to size) or "finish" (the bottom to size, every ring)."""
        h = int(self.value("H", RECONSTRUCTED["H"].value))
        infeed = self.value("D")
        out: list[tuple[float, str]] = []
        if h in (1, 14):
            out += [(z, "rough") for z in _levels(surface, bottom + self.value("AL"), infeed)]
        if h in (4, 14):
            walls = _levels(surface, bottom, infeed)
            out += [(z, "wall") for z in walls[:-1]] + [(bottom, "finish")]
        return out

    def entry(self, x: float, y: float, rotation: float) -> Pt:
        if self.shape is None:
            return (x, y)
        return self._map(x, y, rotation)(self.shape.core_start())

    def _map(self, x: float, y: float, rotation: float) -> Callable[[Pt], Pt]:
        """Shape frame → program coordinates: the reference point EP, the quarter turn of a tall pocket, AR."""
        df, shape = self.df, self.shape
        assert shape is not None
        ep = int(self.value("EP", RECONSTRUCTED["EP"].value))
        dx = dy = 0.0
        turn = 90.0 if self.swap else 0.0
        if ep == 1 and df.code == "G72":
            dx, dy = self.value("LP") / 2, self.value("BP") / 2
        elif ep == 1 and df.code == "G74":
            dx = self.value("LP") / 2 - self.value("BP") / 2
        elif ep == 1 and df.code == "G75":
            an = math.radians(self.value("AN"))
            rp = self.value("RP")
            dx, dy = -rp * math.cos(an), -rp * math.sin(an)
        a = math.radians(rotation)
        ca, sa = math.cos(a), math.sin(a)
        ct, st = math.cos(math.radians(turn)), math.sin(math.radians(turn))

        def to_program(p: Pt) -> Pt:
            u, v = p[0] * ct - p[1] * st + dx, p[0] * st + p[1] * ct + dy
            return (x + u * ca - v * sa, y + u * sa + v * ca)

        return to_program

    def run(self, path: _Path, x: float, y: float, surface: float, rotation: float) -> bool:
        code = self.df.code
        bottom = self.bottom(surface)
        safety = surface + self.value("V")
        if code in ("G81", "G82", "G83"):
            return self._drill(path, x, y, surface, bottom, safety)
        if code == "G84":
            self._tap(path, x, y, bottom, safety)
            return True
        if code == "G85":
            path.go("feed", (x, y, bottom))
            out = self.df.get("E")
            path.go("feed", (x, y, safety), feed=out if out else None)
            return True
        if code == "G86":
            path.go("feed", (x, y, bottom))
            side = RECONSTRUCTED["G86_side"].value * self.value("DR")
            path.go("rapid", (x + side, y, bottom), "off")
            path.go("rapid", (x + side, y, safety), "off")
            path.go("rapid", (x, y, safety), "off")
            return True
        if code == "G87":
            self._bore_mill(path, x, y, bottom, safety)
            return True
        self._pocket(path, x, y, surface, bottom, safety, rotation)
        return True

    def _drill(self, path: _Path, x: float, y: float, surface: float, bottom: float, safety: float) -> bool:
        code = self.df.code
        if code == "G81":
            path.go("feed", (x, y, bottom))
            path.go("rapid", (x, y, safety))
            return True
        depths = self.depths
        vb = self.value("VB", RECONSTRUCTED["VB"].value)
        path.steps = len(depths)
        reached = None
        for k, depth in enumerate(depths):
            path.step = k + 1
            z = surface - depth
            if reached is not None:
                if code == "G83":
                    path.go("rapid", (x, y, safety))
                path.go("rapid", (x, y, min(reached + vb, safety)))
            path.go("feed", (x, y, z))
            reached = z
            if k < len(depths) - 1 and code == "G82":
                path.go("rapid", (x, y, min(z + vb, safety)))
        path.dwell(self.value("U"))
        path.go("rapid", (x, y, safety))
        return True

    def _tap(self, path: _Path, x: float, y: float, bottom: float, safety: float) -> None:
        pitch = self.df.feed or 0.0
        speed = path.template.spindle or self.state.speed
        feed = pitch * speed if pitch * speed > 0 else path.template.feed
        direction = self.df.direction or path.template.spindle_direction
        path.template = dataclasses.replace(
            path.template,
            feed=feed,
            feed_unit="mm/min",
            spindle_direction=direction,
            thread=True,
            pitch=pitch,
        )
        path.go("feed", (x, y, bottom))
        path.go("feed", (x, y, safety), "reverse")

    def _bore_mill(self, path: _Path, x: float, y: float, bottom: float, safety: float) -> None:
        rc = self.value("R") - self.rt
        pitch = self.value("D")
        path.go("feed", (x + rc, y, safety))
        turns = (safety - bottom) / pitch
        full = math.floor(turns + 1e-9)
        z = safety
        for _ in range(full):
            z -= pitch
            path.arc((x + rc, y, max(z, bottom)), (x, y), True, full=True)
        rest = turns - full
        if rest > 1e-9:
            a = 2 * math.pi * rest
            path.arc((x + rc * math.cos(a), y + rc * math.sin(a), bottom), (x, y), True)
        end = path.pos
        path.arc((end[0], end[1], bottom), (x, y), True, full=True)
        path.go("feed", (x, y, bottom))
        path.go("rapid", (x, y, safety))

    def _pocket(
        self, path: _Path, x: float, y: float, surface: float, bottom: float, safety: float, rotation: float
    ) -> None:
        shape = self.shape
        assert shape is not None
        to_program = self._map(x, y, rotation)
        plunge = self.value("E") or None
        helical = int(self.value("O", RECONSTRUCTED["O"].value)) == 2
        conventional = int(self.value("Q", RECONSTRUCTED["Q"].value)) == 2
        levels = self._plan_levels(surface, bottom)
        path.steps = len(levels)
        nominal = self.nominal or shape
        cs = to_program(shape.core_start())
        top = safety

        def follow(segs: list[Seg], z: float) -> None:
            for s in segs:
                end = to_program(s.end)
                if s.centre is None:
                    path.go("feed", (end[0], end[1], z))
                else:
                    path.arc((end[0], end[1], z), to_program(s.centre), s.ccw)

        for k, (z, what) in enumerate(levels):
            path.step = k + 1
            use = nominal if what in ("wall", "finish") else shape
            hr = RECONSTRUCTED["O2_radius"].value * self.rt
            if helical and hr > 1e-3 and use.reach >= hr:
                c = (shape.core_start()[0] + hr, shape.core_start()[1])
                p = to_program(c)
                path.go("feed", (p[0], p[1], top), feed=plunge)
                path.arc((p[0], p[1], z), cs, True, feed=plunge, full=True)
                path.go("feed", (cs[0], cs[1], z))
            else:
                path.go("feed", (cs[0], cs[1], z), feed=plunge)
            core = use.core()
            follow(core, z)
            offsets = _offsets(use.reach, self.step_over) if what != "wall" else [use.reach]
            for t in offsets:
                start, ring = use.ring(t)
                p = to_program(start)
                path.go("feed", (p[0], p[1], z))
                follow(_reversed(start, ring) if conventional else ring, z)
            if offsets or core:
                end = to_program(use.core_end())
                path.go("feed", (end[0], end[1], z))
                follow(_reversed(use.core_start(), core), z)
            top = z
        path.go("rapid", (path.pos[0], path.pos[1], safety))


def steps(
    depth: float, infeed: float, first: float | None, reduce: float, smallest: float | None, limit: int
) -> list[float] | None:
    """The depths (from the surface) reached by the steps of G82/G83: the first DA (default D), then
    D − (k − 1) · DR but not below DM (default RECONSTRUCTED, at most D); the last one ends at the bottom.
    None: more than `limit` steps."""
    least = smallest if smallest is not None else min(RECONSTRUCTED["DM"].value, infeed)
    out: list[float] = []
    reached = 0.0
    k = 1
    while reached < depth - EPS:
        if len(out) >= limit:
            return None
        size = first if k == 1 and first is not None else infeed - (k - 1) * reduce
        size = max(size, least, 1e-3)
        reached = min(reached + size, depth)
        out.append(reached)
        k += 1
    return out


def reconstructed_markdown() -> str:
    """The table of reconstructed choices for docs/pal-milling.md."""
    rows = ["| Wort / Regel | Wahl (Deutsch) | Choice (English) | Sicherheit |", "|---|---|---|---|"]
    rows += [f"| {key} | {c.de} | {c.en} | {c.certainty} |" for key, c in RECONSTRUCTED.items()]
    return "\n".join(rows) + "\n"
