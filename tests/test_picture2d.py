"""The 2D picture of a program's result (core/picture2d.py), what the page shows while the 3D view is off: the
stock's outline, the depths as a colour ramp with a legend in mm, the tool-centre path (rapid dashed, feed
solid), the programmed contour, axes with coordinates, the workpiece zero, the blocks an error skipped; for
turning the drawing view in half section; its cost bounded and the caps said."""

from __future__ import annotations

import base64
import re
import struct
import zlib
from pathlib import Path
from xml.etree import ElementTree as ET

import numpy as np
import pytest

from core.exercises import load_exercise
from core.interpreter.state import RunSetup
from core.picture2d import (
    CONTOUR,
    ERROR,
    FEED,
    RAPID,
    PictureLimits,
    depth_levels,
    lathe_picture,
    mill_picture,
    nice_step,
    num,
    skipped_blocks,
)
from core.pipeline import run
from core.sim import DEFAULT_LATHE_TOOLS, Blank, Stock, simulate, simulate_turning

ROOT = Path(__file__).parents[1]
SVG = "{http://www.w3.org/2000/svg}"
STOCK = Stock(0, 0, -30, 80, 70, 0)


def _exercise(slug: str, folder: str = "pal-mill"):  # type: ignore[no-untyped-def]
    return load_exercise(ROOT / "exercises" / folder / f"{slug}.yaml")


def _mill(
    text: str,
    stock: Stock = STOCK,
    tools=None,
    lang: str = "de",  # type: ignore[no-untyped-def]
    limits: PictureLimits | None = None,
    resolution: float = 0.25,
):
    setup = RunSetup(tools=tools) if tools is not None else RunSetup()
    toolpath = run(text, "pal-mill", setup)
    result = simulate(toolpath, stock, setup.tools, resolution)
    return mill_picture(toolpath, result.heightmap, stock, lang, **({"limits": limits} if limits else {}))


def _reference(slug: str, lang: str = "de"):  # type: ignore[no-untyped-def]
    ex = _exercise(slug)
    tools = ex.tool_table()
    setup = RunSetup(
        tools=tools, zero_offsets=tuple(ex.zero_offsets.items()), subprograms=tuple(ex.subprograms.items())
    )
    toolpath = run(ex.reference, ex.dialect, setup)
    stock = ex.stock.stock()
    return mill_picture(toolpath, simulate(toolpath, stock, tools, 0.25).heightmap, stock, lang)


def _parse(svg: str) -> ET.Element:
    root = ET.fromstring(svg)
    assert root.tag == f"{SVG}svg"
    return root


def _texts(root: ET.Element) -> list[str]:
    return ["".join(t.itertext()) for t in root.iter(f"{SVG}text")]


def _paths(root: ET.Element, stroke: str) -> list[ET.Element]:
    return [p for p in root.iter(f"{SVG}path") if p.get("stroke") == stroke]


def _to_px(info: dict, u: float, v: float) -> tuple[float, float]:
    u0, v1, scale, left, top = map(float, info["frame"].split())
    return left + (u - u0) * scale, top + (v1 - v) * scale


def _points(d: str) -> list[tuple[float, float]]:
    """The end points of every command of a path's d (M, L, and A's end)."""
    out = []
    for _, args in re.findall(r"([MLA])([^MLAVZ]*)", d):
        values = [float(v) for v in args.replace(",", " ").split()]
        out.append((values[-2], values[-1]))
    return out


def _png_size(root: ET.Element) -> tuple[int, int]:
    image = next(root.iter(f"{SVG}image"))
    data = base64.b64decode(image.get("href", "").split(",", 1)[1])
    assert data.startswith(b"\x89PNG")
    return struct.unpack(">II", data[16:24])


def _png_pixels(root: ET.Element) -> np.ndarray:
    data = base64.b64decode(next(root.iter(f"{SVG}image")).get("href", "").split(",", 1)[1])
    width, height = struct.unpack(">II", data[16:24])
    raw, pos = b"", 8
    while pos < len(data):
        length = struct.unpack(">I", data[pos : pos + 4])[0]
        if data[pos + 4 : pos + 8] == b"IDAT":
            raw += data[pos + 8 : pos + 8 + length]
        pos += 12 + length
    rows = np.frombuffer(zlib.decompress(raw), dtype=np.uint8).reshape(height, 1 + 3 * width)
    return rows[:, 1:].reshape(height, width, 3)


def test_plan_view_of_a_milling_exercise() -> None:
    """PAL-01: two 2 mm deep steps along the bottom and the right edge, milled with G42 by a Ø25 end mill."""
    picture = _reference("pal-01-g1-gerade")
    root = _parse(picture.svg)
    info = picture.info
    assert info["view"] == "mill" and info["path_cut"] == "false" and info["errors"] == ""
    assert info["raster"] == "320x280" and info["cell"] == 0.25
    # the stock's outline: 80 × 70 mm at the picture's scale, its lower left corner at the zero
    scale = float(info["frame"].split()[2])
    outline = [r for r in root.iter(f"{SVG}rect") if r.get("stroke") == "#262a31" and r.get("fill") == "none"]
    assert len(outline) == 1
    x, y = _to_px(info, 0, 70)
    box = outline[0]
    assert abs(float(box.get("x")) - x) < 0.02 and abs(float(box.get("y")) - y) < 0.02
    assert (
        abs(float(box.get("width")) - 80 * scale) < 0.02 and abs(float(box.get("height")) - 70 * scale) < 0.02
    )
    # the depth raster fills the stock's outline
    image = next(root.iter(f"{SVG}image"))
    assert image.get("width") == box.get("width") and image.get("height") == box.get("height")
    # depths: the top face grey, the 2 mm step along the ramp; the legend names Z 0 and Z-2 in mm
    texts = _texts(root)
    assert "Tiefe Z in mm" in texts and "0" in texts and "-2" in texts
    pixels = _png_pixels(root)
    assert tuple(pixels[100, 100]) == (226, 229, 234)  # the middle of the block: untouched top face
    corner = pixels[-10, -10]  # lower right: in both steps
    assert tuple(corner) != (226, 229, 234) and corner[0] > corner[2]  # a warm colour, not grey
    # the feed path: the tool centre 12.5 mm right of the contour (G42, Ø25) along Y-2.5, then X82.5
    feed = _paths(root, FEED)
    assert len(feed) == 1
    points = _points(feed[0].get("d", ""))
    for u, v in ((70.0 - 0.0, -2.5), (82.5, 84.0)):
        px = _to_px(info, u, v)
        assert min(abs(a - px[0]) + abs(b - px[1]) for a, b in points) < 0.05, (u, v)
    # the programmed contour (green) on Y10 and X70; rapid moves dashed orange
    contour = _points(_paths(root, CONTOUR)[0].get("d", ""))
    for u, v in ((70.0, 10.0), (70.0, 84.0)):
        px = _to_px(info, u, v)
        assert min(abs(a - px[0]) + abs(b - px[1]) for a, b in contour) < 0.05, (u, v)
    rapid = _paths(root, RAPID)
    assert rapid and rapid[0].get("stroke-dasharray")
    assert not feed[0].get("stroke-dasharray")
    # the retract to X250 Y150 leaves the picture: where to is written at its edge
    assert any("→ X250 Y150 Z250" in t for t in texts)
    # axes with coordinates, the zero symbol at the zero, the legend
    for label in (
        "X",
        "Y",
        "20",
        "40",
        "60",
        "80",
        "Eilgang",
        "Vorschub (Werkzeugmitte)",
        "programmierte Kontur",
        "Werkstücknullpunkt",
        "Raster 0,25 mm",
    ):
        assert label in texts, label
    zero = _to_px(info, 0, 0)
    assert any(
        abs(float(c.get("cx")) - zero[0]) < 0.02
        and abs(float(c.get("cy")) - zero[1]) < 0.02
        and c.get("stroke") == "#262a31"
        for c in root.iter(f"{SVG}circle")
    )


@pytest.mark.parametrize(("slug", "sweep"), [("pal-05-g2-kreisbogen", "0"), ("pal-06-g3-kreisbogen", "1")])
def test_arcs_are_drawn_as_arcs_in_their_direction(slug: str, sweep: str) -> None:
    """G2 clockwise, G3 counter-clockwise as seen from above (SVG's y points down: sweep 0 is clockwise)."""
    root = _parse(_reference(slug).svg)
    arcs = re.findall(r"A([\d.]+) [\d.]+ 0 (\d) (\d)", _paths(root, FEED)[0].get("d", ""))
    assert arcs and all(s == sweep for _, _, s in arcs)


def test_full_circle_and_plunges() -> None:
    text = "N1 T1 TC1 M6\nN2 S2000 F200 M3\nN3 G0 X40 Y35 Z2\nN4 G1 Z-3\nN5 G1 X55\nN6 G2 X55 Y35 I-15 J0\nN7 G0 Z50\nN8 M30\n"
    picture = _mill(text)
    root = _parse(picture.svg)
    d = _paths(root, FEED)[0].get("d", "")
    assert len(re.findall("A", d)) == 2  # a full circle: two halves
    rings = [c for c in root.iter(f"{SVG}circle") if c.get("stroke") == FEED]
    assert len(rings) == 2  # the plunge at X40 Y35, and the legend's symbol
    assert "Eintauchen" in _texts(root)


def test_blocks_an_error_kept_from_running_are_marked() -> None:
    ex = _exercise("pal-13-g41-aussenkontur")
    text = ex.reference.replace("N60 G1 X15 Y75", "N60 G1 X15 Y75 Q7")
    setup = RunSetup(tools=ex.tool_table())
    toolpath = run(text, "pal-mill", setup)
    skipped = skipped_blocks(toolpath)
    assert 6 in skipped
    stock = ex.stock.stock()
    picture = mill_picture(toolpath, simulate(toolpath, stock, setup.tools, 0.5).heightmap, stock)
    root = _parse(picture.svg)
    assert picture.info["errors"] == ",".join(map(str, skipped))
    texts = _texts(root)
    assert any(t.startswith(("Zeile 6", "Zeilen 6")) for t in texts), texts
    assert any(t.startswith("Satz mit Fehler, nicht ausgeführt: Zeile") for t in texts)
    # the marker stands where the tool was when line 6 was skipped (after N50 at X15 Y-15, from the G41 move)
    _, position = toolpath.state_at(6)
    x, y = _to_px(picture.info, position[0], position[1])
    assert any(
        c.get("stroke") == ERROR and abs(float(c.get("cx")) - x) < 0.05 and abs(float(c.get("cy")) - y) < 0.05
        for c in root.iter(f"{SVG}circle")
    )
    # a program without errors has no marker
    clean = _parse(mill_picture(run(ex.reference, "pal-mill", setup), None, stock).svg)
    assert not [c for c in clean.iter(f"{SVG}circle") if c.get("stroke") == ERROR]


def test_the_caps_are_kept_and_said() -> None:
    lines = ["N1 T1 TC1 M6", "N2 S2000 F500 M3", "N3 G0 X5 Y5 Z2", "N4 G1 Z-1"]
    lines += [f"N{10 + k} G1 X{5 + (k % 2) * 70} Y{5 + k * 0.5:.1f}" for k in range(120)]
    text = "\n".join([*lines, "N999 M30"]) + "\n"
    limits = PictureLimits(raster=60, points=40)
    picture = _mill(text, limits=limits, resolution=0.5)
    root = _parse(picture.svg)
    assert picture.info["path_cut"] == "true" and picture.info["points"] <= 40
    assert picture.info["points_total"] > 120
    width, height = _png_size(root)
    assert max(width, height) <= 60 and picture.info["raster"] == f"{width}x{height}"
    assert float(picture.info["cell"]) >= 0.5 * 160 / 60 - 1e-9  # cells pooled: 160 cells → 60 pixels
    texts = _texts(root)
    assert any(t.startswith("Weg gekürzt:") and f"{picture.info['points']} von" in t for t in texts), texts
    # drawn elements stay few: one path per kind and halo, not one per move
    assert len(list(root.iter(f"{SVG}path"))) < 40


def test_english_and_nothing_undefined() -> None:
    picture = _reference("pal-14-g42-innenkontur", "en")
    texts = _texts(_parse(picture.svg))
    for label in ("Depth Z in mm", "Rapid", "Feed (tool centre)", "Workpiece zero", "raster 0.25 mm"):
        assert label in texts, label
    for svg in (picture.svg, _reference("pal-14-g42-innenkontur").svg):
        assert not re.search(
            r"\b(NaN|None|null|undefined|inf)\b", svg.split("base64,")[0] + svg.split('"/>', 1)[-1]
        )


def test_empty_program_shows_the_stock() -> None:
    picture = mill_picture(run("", "pal-mill"), None, STOCK)
    root = _parse(picture.svg)
    assert "Noch keine Bewegung." in _texts(root)
    assert not _paths(root, FEED) and not list(root.iter(f"{SVG}image"))


def test_depth_levels_and_helpers() -> None:
    heights = np.zeros((10, 10))
    heights[:, :3] = -2.0
    heights[:2, :] = -5.004
    assert depth_levels(heights, 0.0, -30.0) == [-2.0, -5.0]
    assert depth_levels(np.zeros((3, 3)), 0.0, -30.0) == []
    assert [nice_step(s, 7) for s in (80, 7, 0.9, 140)] == [20, 1, 0.2, 20]
    assert num(-2.5) == "-2,5" and num(-2.5, "en") == "-2.5" and num(-0.0001) == "0" and num(12.0) == "12"


def test_turning_drawing_view() -> None:
    """A Ø40 bar turned to Ø30 over 20 mm: the upper half cut open and hatched, the path above the axis, the
    X axis as diameters."""
    text = (
        "%\nO0001\nN10 G95 G97 S1200 M4\nN20 T0101\nN30 G0 X30 Z2\nN40 G1 Z0 F0.2\nN50 G1 Z-20\n"
        "N60 G1 X42\nN80 G0 X100 Z100\nN90 M30\n"
    )
    toolpath = run(text, "traub-tx8d", RunSetup(tools=DEFAULT_LATHE_TOOLS))
    blank = Blank(40.0, 60.0)
    profile = simulate_turning(toolpath, blank, DEFAULT_LATHE_TOOLS, 0.1).profile
    picture = lathe_picture(toolpath, profile, blank)
    root = _parse(picture.svg)
    info = picture.info
    assert info["view"] == "lathe"
    texts = _texts(root)
    for label in ("X (Ø)", "Z", "Schnitt", "Ansicht", "Eilgang", "Werkstücknullpunkt", "40", "-20"):
        assert label in texts, label
    section = [p for p in root.iter(f"{SVG}path") if p.get("fill") == "url(#hatch)"]
    assert len(section) == 1
    points = _points(section[0].get("d", ""))
    ys = [y for _, y in points]
    axis_y = _to_px(info, 0, 0)[1]
    assert max(ys) <= axis_y + 0.01  # the section is the upper half
    scale = float(info["frame"].split()[2])
    for u, v in ((-60, 20), (-20.5, 20), (-19.5, 15), (0, 15)):  # Ø40 at the back, the shoulder at Z-20, Ø30
        x, y = _to_px(info, u, v)
        assert min(abs(a - x) + abs(b - y) for a, b in points) < 0.6 * scale, (u, v)
    # the feed path at the radius (X30 → 15 mm above the axis), drawn from Z0 to Z-20
    feed = _points(_paths(root, FEED)[0].get("d", ""))
    a, b = _to_px(info, 0, 15), _to_px(info, -20, 15)
    for target in (a, b):
        assert min(abs(x - target[0]) + abs(y - target[1]) for x, y in feed) < 0.05
