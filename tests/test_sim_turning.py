"""The turning simulation (core.sim.turning): volumes of turned parts against hand formulas, the events with
their lines, the cycle time under G95/G96/G92, the CLI (`paltrainer simulate --dialect traub-tx8d --blank`),
the revolved STL and the half-section PNG."""

from __future__ import annotations

import itertools
import json
import math
import struct
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from core.cli import main
from core.interpreter.state import RunSetup
from core.pipeline import run
from core.sim import parse_tool_table, tool_table_yaml
from core.sim.insert import insert_of
from core.sim.lathe_export import half_section_png, revolved_mesh
from core.sim.turning import Blank, TurningResult, simulate_turning
from core.toolpath import Move
from core.tools import Tool, ToolTable, turning_tool

SEEDS = Path(__file__).parent / "seeds" / "traub"
RAPID = 12_000.0  # mm/min, LatheMachine's default
CHANGE = 1.0  # s per turret index


def turn(program: str, blank: Blank, tools: ToolTable, resolution: float = 0.05) -> TurningResult:
    toolpath = run(program, "traub-tx8d", RunSetup(tools=tools))
    assert [d.code for d in toolpath.diagnostics if d.severity.value == "error"] == []
    return simulate_turning(toolpath, blank, tools, resolution)


def events(result: TurningResult) -> list[tuple[str, int]]:
    return [(e.code, e.span.line) for e in result.events]


def table(yaml_text: str) -> ToolTable:
    return parse_tool_table(yaml_text)


OUTSIDE = table(
    "tools: [{number: 1, kind: turning, diameter: 0.8, nose_radius: 0.4, quadrant: 1, insert: C}]"
)
SHARP = ToolTable({1: turning_tool(1, 0.0, 1)})

CYLINDER = """G95
G97 S1000 T0101 M4
G0 X42 Z2
G1 X30 F0.2
G1 Z-20
G1 X42
G0 X100 Z100
M30
"""


@pytest.mark.parametrize("tools", [SHARP, OUTSIDE], ids=["R0", "R0.4"])
def test_cylinder_turned_from_40_to_30_over_20mm(tools: ToolTable) -> None:
    result = turn(CYLINDER, Blank(40, 100), tools)
    want = math.pi * (20**2 - 15**2) * 20
    assert result.removed_volume == pytest.approx(want, rel=0.005)
    assert result.remaining_volume == pytest.approx(math.pi * 20**2 * 100 - want, rel=0.001)
    assert result.events == []
    # the profile: Ø30 from the face to Z−19, the blank's Ø40 behind the shoulder
    p = result.profile
    assert 2 * p.outer[np.searchsorted(p.zs, -10.0)] == pytest.approx(30.0, abs=0.02)
    assert 2 * p.outer[np.searchsorted(p.zs, -25.0)] == pytest.approx(40.0, abs=0.02)


def test_nose_radius_leaves_its_radius_in_the_shoulder_corner() -> None:
    # without SRK the tip is programmed: the nose centre runs R above and R right of it, so the corner at
    # Z−20 keeps a fillet of R (the same cylinder with a sharp tool has a sharp corner)
    sharp = turn(CYLINDER, Blank(40, 100), SHARP).profile
    round_ = turn(CYLINDER, Blank(40, 100), OUTSIDE).profile
    k = np.searchsorted(
        sharp.zs, -19.95
    )  # under the 3° clearance of the 93° edge: cut by both moves together
    assert 2 * sharp.outer[k] == pytest.approx(30.0, abs=0.01)
    assert 2 * round_.outer[np.searchsorted(sharp.zs, -19.9)] > 30.2


def test_srk_turns_the_contour_with_a_nose_radius() -> None:
    # G46 with P1: the moves are the nose centre's, R above the contour; the shoulder face stays at Z−20
    program = (
        "G95\nG97 S1000 T0101 M4\nG46\nG0 X30 Z2\nG1 Z-20 F0.2\nG1 X42\nG0 X44 A90\nG40\nG0 X100 Z100\nM30\n"
    )
    result = turn(program, Blank(40, 100), OUTSIDE)
    p = result.profile
    assert 2 * p.outer[np.searchsorted(p.zs, -10.0)] == pytest.approx(30.0, abs=0.02)
    assert 2 * p.outer[np.searchsorted(p.zs, -20.1)] == pytest.approx(40.0, abs=0.02)
    assert result.removed_volume == pytest.approx(math.pi * (20**2 - 15**2) * 20, rel=0.005)


def test_chamfer_4mm_at_45_degrees() -> None:
    program = "G95\nG97 S1000 T0101 M4\nG0 X28 Z2\nG1 X40 Z-4 F0.1\nG1 X44\nG0 X100 Z100\nM30\n"
    result = turn(program, Blank(40, 100), SHARP)
    want = math.pi * 20**2 * 4 - math.pi * 4 * (16**2 + 16 * 20 + 20**2) / 3
    assert result.removed_volume == pytest.approx(want, rel=0.005)
    assert result.events == []


GROOVE = table(
    "tools: [{number: 7, kind: turning, diameter: 0.4, nose_radius: 0.2, quadrant: 1, insert: groove, "
    "width: 3}]"
)


def test_groove_of_width_b_with_a_grooving_insert() -> None:
    # the left corner is the reference (P1): the groove runs from Z−10 to Z−7, Ø40 → Ø30
    program = "G95\nG97 S800 T0707 M4\nG0 X42 Z-10\nG1 X30 F0.05\nG0 X42\nG0 X100 Z100\nM30\n"
    result = turn(program, Blank(40, 100), GROOVE)
    assert result.removed_volume == pytest.approx(math.pi * (20**2 - 15**2) * 3, rel=0.005)
    assert result.events == []
    p = result.profile
    assert 2 * p.outer[np.searchsorted(p.zs, -8.5)] == pytest.approx(30.0, abs=0.02)
    assert 2 * p.outer[np.searchsorted(p.zs, -10.2)] == pytest.approx(40.0, abs=0.02)
    assert 2 * p.outer[np.searchsorted(p.zs, -6.8)] == pytest.approx(40.0, abs=0.02)


BORING = table("tools: [{number: 9, kind: turning, diameter: 0.1, nose_radius: 0.0, quadrant: 4, insert: C}]")


def test_bore_widened_from_inside_with_a_boring_bar() -> None:
    program = "G95\nG97 S1000 T0909 M4\nG0 X24 Z2\nG1 Z-15 F0.1\nG1 X20\nG0 Z2\nG0 X100 Z100\nM30\n"
    result = turn(program, Blank(40, 100, bore=20), BORING)
    assert result.removed_volume == pytest.approx(math.pi * (12**2 - 10**2) * 15, rel=0.005)
    assert result.events == []
    p = result.profile
    assert 2 * p.inner[np.searchsorted(p.zs, -5.0)] == pytest.approx(24.0, abs=0.02)
    assert 2 * p.inner[np.searchsorted(p.zs, -20.0)] == pytest.approx(20.0, abs=0.02)
    assert 2 * p.outer[np.searchsorted(p.zs, -5.0)] == pytest.approx(40.0, abs=0.02)


def test_a_drill_on_the_axis_bores_from_the_face() -> None:
    drill = table(
        "tools: [{number: 3, kind: twist_drill, diameter: 10, point_angle: 118, cutting_length: 60}]"
    )
    program = "G95\nG97 S1000 T0303 M3\nG0 X0 Z2\nG1 Z-30 F0.1\nG0 Z2\nG0 X100 Z100\nM30\n"
    result = turn(program, Blank(40, 100), drill)
    cone = math.pi * 25 * (5 / math.tan(math.radians(59))) / 3
    assert result.removed_volume == pytest.approx(
        math.pi * 25 * 30 - (math.pi * 25 * 5 / math.tan(math.radians(59)) - cone), rel=0.005
    )
    assert result.events == []


# --- events, each on its line -------------------------------------------------------------------------


def test_rapid_into_the_material() -> None:
    program = "G95\nG97 S1000 T0101 M4\nG0 X42 Z2\nG0 X30 Z-5\nG0 X100 Z100\nM30\n"
    assert ("SIM-E001", 4) in events(turn(program, Blank(40, 100), OUTSIDE))


def test_cutting_with_the_spindle_stopped() -> None:
    program = "G95\nG97 S1000 T0101\nG0 X42 Z2\nG1 X36 F0.2\nG1 Z-10\nG0 X100 Z100\nM30\n"
    result = simulate_turning(run(program, "traub-tx8d", RunSetup(tools=OUTSIDE)), Blank(40, 100), OUTSIDE)
    assert ("SIM-E006", 5) in events(result)


def test_cutting_into_the_chuck_jaws() -> None:
    # Ø40 × 60 held on its last 20 mm: the jaws reach from Z−60 to Z−40
    program = CYLINDER.replace("G1 Z-20", "G1 Z-45")
    result = turn(program, Blank(40, 60, chuck_length=20), OUTSIDE)
    assert events(result)[0] == ("SIM-E012", 5)
    assert "Z-40" in result.events[0].message
    assert turn(CYLINDER, Blank(40, 60, chuck_length=20), OUTSIDE).events == []


def test_cut_deeper_than_the_cutting_length() -> None:
    # a C insert takes 8 mm at most; 10 mm radial depth in one pass is too deep (the holder still clears)
    program = "G95\nG97 S500 T0101 M4\nG0 X40 Z2\nG1 Z-20 F0.2\nG1 X62\nG0 X100 Z100\nM30\n"
    assert events(turn(program, Blank(60, 100), OUTSIDE)) == [("SIM-E013", 4)]
    shallow = "G95\nG97 S500 T0101 M4\nG0 X46 Z2\nG1 Z-20 F0.2\nG1 X62\nG0 X100 Z100\nM30\n"
    assert events(turn(shallow, Blank(60, 100), OUTSIDE)) == []


def test_the_holder_touches_the_part() -> None:
    # plunging 20 mm deep beside the material with an 80° insert: the holder above the insert hits the shoulder
    program = "G95\nG97 S500 T0101 M4\nG0 X102 Z-20\nG1 X60 F0.1\nG0 X102\nG0 X150 Z100\nM30\n"
    assert ("SIM-E011", 4) in events(turn(program, Blank(100, 100), OUTSIDE))


def test_the_boring_bar_touches_a_narrow_bore() -> None:
    # a Ø16 boring bar in a Ø14 bore
    program = "G95\nG97 S1000 T0909 M4\nG0 X16 Z2\nG1 Z-15 F0.1\nG1 X12\nG0 Z2\nG0 X100 Z100\nM30\n"
    assert ("SIM-E011", 4) in events(turn(program, Blank(40, 100, bore=14), BORING))


def test_grooving_tool_moved_along_z_while_cutting() -> None:
    program = "G95\nG97 S800 T0707 M4\nG0 X42 Z-10\nG1 X36 F0.05\nG1 Z-20\nG0 X42\nG0 X100 Z100\nM30\n"
    assert events(turn(program, Blank(40, 100), GROOVE)) == [("SIM-E014", 5)]


def test_threading_tool_plunged_radially() -> None:
    thread = table(
        "tools: [{number: 8, kind: turning, diameter: 0.2, nose_radius: 0.1, quadrant: 1, insert: thread}]"
    )
    program = "G95\nG97 S800 T0808 M4\nG0 X42 Z-10\nG1 X37 F0.05\nG0 X42\nG0 X100 Z100\nM30\n"
    result = turn(program, Blank(40, 100), thread)
    assert ("SIM-E014", 4) in events(result)
    assert "Gewindedrehmeißel" in result.events[0].message and "threading tool" in result.events[0].message_en


# --- cycle time ------------------------------------------------------------------------------------------


def _rapids(program: str, tools: ToolTable) -> float:
    moves = [c for c in run(program, "traub-tx8d", RunSetup(tools=tools)).commands if isinstance(c, Move)]
    return sum(math.dist(m.start, m.end) for m in moves if m.kind == "rapid") / RAPID * 60


def test_cycle_time_g95_feed_per_revolution() -> None:
    # 6 + 22 + 6 mm at 0.2 mm × 1000 1/min = 200 mm/min
    result = turn(CYLINDER, Blank(40, 100), SHARP)
    assert result.cycle_time == pytest.approx(34 / 200 * 60 + _rapids(CYLINDER, SHARP) + CHANGE, rel=1e-6)


def test_cycle_time_g96_facing_to_the_centre_limited_by_g92() -> None:
    # V = 200 m/min: n = 1000·V/(π·D) rises as the tool faces towards the centre, until G92 S2000 holds it
    program = "G95\nG96 V200 T0101 M4\nG92 S2000\nG0 X42 Z-1\nG1 X0 F0.1\nG0 Z2\nG0 X100 Z100\nM30\n"
    f, v, limit, r0 = 0.1, 200.0, 2000.0, 21.0
    rc = 1000 * v / (2 * math.pi * limit)  # radius below which the limit holds
    minutes = (math.pi * (r0**2 - rc**2) / (1000 * v) + rc / limit) / f
    result = turn(program, Blank(40, 100), SHARP)
    assert result.cycle_time == pytest.approx(minutes * 60 + _rapids(program, SHARP) + CHANGE, rel=1e-4)


def test_cycle_time_g96_along_z_uses_the_speed_at_the_diameter() -> None:
    program = "G95\nG96 V150 T0101 M4\nG92 S3000\nG0 X30 Z2\nG1 Z-40 F0.2\nG0 X100 Z100\nM30\n"
    n = 1000 * 150 / (math.pi * 30)
    result = turn(program, Blank(40, 100), SHARP)
    assert result.cycle_time == pytest.approx(
        42 / (0.2 * n) * 60 + _rapids(program, SHARP) + CHANGE, rel=1e-6
    )


# --- tool table, seeds, CLI, exports ---------------------------------------------------------------------


def test_insert_fields_round_trip_through_the_tool_table() -> None:
    yaml_text = tool_table_yaml(
        GROOVE.with_tool(
            Tool(2, "turning", 1.6, "SVJBR", nose_radius=0.8, quadrant=2, insert="V", holder=20.0)
        )
    )
    again = parse_tool_table(yaml_text)
    assert again.tools[7].insert == "groove" and again.tools[7].width == 3.0
    assert again.tools[7].cutting_length is None
    assert again.tools[2].insert == "V" and again.tools[2].holder == 20.0
    assert insert_of(again.tools[2], 2).direction == 1  # P2 cuts towards +Z


@pytest.mark.parametrize(
    "entry,word",
    [("insert: X", "insert"), ("insert: groove", "width"), ("insert_angle: 200", "insert_angle")],
)
def test_bad_insert_fields_are_named(entry: str, word: str) -> None:
    from core.sim import ToolTableError

    with pytest.raises(ToolTableError, match=word):
        parse_tool_table(
            f"tools: [{{number: 1, kind: turning, diameter: 0.8, nose_radius: 0.4, quadrant: 1, {entry}}}]"
        )


def test_every_traub_seed_simulates() -> None:
    for path in sorted(SEEDS.glob("*.nc")):
        toolpath = run(path.read_text(encoding="utf-8"), "traub-tx8d")
        result = simulate_turning(toolpath, Blank(100, 160))
        assert result.complete, path.name
        assert 0 <= result.removed_volume <= Blank(100, 160).volume + 1e-6, path.name
        assert result.cycle_time >= 0, path.name


def _closed(triangles: np.ndarray) -> bool:
    edges = Counter()
    for a, b, c in triangles.tolist():
        for e in ((a, b), (b, c), (c, a)):
            edges[e] += 1
    return all(edges[(b, a)] == n for (a, b), n in edges.items())


@pytest.mark.parametrize("blank", [Blank(40, 100), Blank(40, 100, bore=20)], ids=["bar", "tube"])
def test_revolved_mesh_is_closed_and_holds_the_volume(blank: Blank) -> None:
    result = turn(CYLINDER, blank, OUTSIDE)
    vertices, triangles = revolved_mesh(result.profile, sections=256)
    assert _closed(triangles)
    v = vertices.astype(np.float64)[triangles]
    volume = float(np.sum(np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])))) / 6
    assert volume == pytest.approx(result.remaining_volume, rel=0.002)


def test_a_parted_off_piece_is_a_second_closed_solid() -> None:
    groove = GROOVE.with_tool(
        Tool(
            7,
            "turning",
            0.4,
            "Abstechen",
            nose_radius=0.2,
            quadrant=1,
            insert="groove",
            width=3.0,
            cutting_length=25.0,
        )
    )
    program = "G95\nG97 S800 T0707 M4\nG0 X42 Z-10\nG1 X0 F0.05\nG0 X42\nG0 X100 Z100\nM30\n"
    result = turn(program, Blank(40, 100), groove)
    _, triangles = revolved_mesh(result.profile)
    assert _closed(triangles)
    assert result.profile.outer[np.searchsorted(result.profile.zs, -8.5)] == 0.0


def test_cli_simulate_turning_json_stl_png(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    nc = tmp_path / "welle.nc"
    nc.write_text(CYLINDER, encoding="utf-8")
    tools = tmp_path / "tools.yaml"
    tools.write_text(tool_table_yaml(SHARP), encoding="utf-8")
    stl, png = tmp_path / "teil.stl", tmp_path / "teil.png"
    code = main(
        [
            "simulate",
            str(nc),
            "--dialect",
            "traub-tx8d",
            "--blank",
            "bar:40,100,25",
            "--tools",
            str(tools),
            "--json",
            "--stl",
            str(stl),
            "--png",
            str(png),
        ]
    )
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    assert out["removed_volume_mm3"] == pytest.approx(math.pi * (20**2 - 15**2) * 20, rel=0.005)
    assert out["remaining_volume_mm3"] > 0 and out["cycle_time_s"] > 0 and out["events"] == []
    assert out["blank"] == {
        "diameter": 40.0,
        "bore": 0.0,
        "length": 100.0,
        "clamp": 25.0,
        "jaw_diameter": 80.0,
    }
    data = stl.read_bytes()
    assert struct.unpack("<I", data[80:84])[0] * 50 + 84 == len(data)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_cli_simulate_turning_reports_events_and_exit_code(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    nc = tmp_path / "crash.nc"
    nc.write_text("G95\nG97 S1000 T0101 M4\nG0 X42 Z2\nG0 X30 Z-5\nG0 X100 Z100\nM30\n", encoding="utf-8")
    assert main(["simulate", str(nc), "--dialect", "traub-tx8d", "--blank", "tube:40,20,100"]) == 1
    assert f"{nc}:4: Fehler SIM-E001" in capsys.readouterr().out


@pytest.mark.parametrize("bad", ["bar:40", "tube:40,50,100", "bar:40,100,100", "cone:1,2", "bar:a,b"])
def test_cli_bad_blank_is_a_usage_error(tmp_path: Path, bad: str, capsys: pytest.CaptureFixture[str]) -> None:
    nc = tmp_path / "x.nc"
    nc.write_text(CYLINDER, encoding="utf-8")
    assert main(["simulate", str(nc), "--dialect", "traub-tx8d", "--blank", bad]) == 2
    assert "bar:D,L" in capsys.readouterr().err


def test_half_section_png_draws_material_above_and_the_view_below() -> None:
    result = turn(CYLINDER, Blank(40, 100), OUTSIDE)
    png = half_section_png(result.profile, Blank(40, 100))
    width, height = struct.unpack(">II", png[16:24])
    assert width > height > 0


def test_cycle_time_g96_along_a_taper_and_an_arc() -> None:
    # V = 150 m/min below the G92 limit everywhere: time = ∫ ds / (f · 1000·V / (2π r))
    f, v = 0.2, 150.0
    taper = "G95\nG96 V150 T0101 M4\nG92 S4000\nG0 X30 Z0\nG1 X40 Z-10 F0.2\nG0 X100 Z100\nM30\n"
    length = math.hypot(5, 10)
    minutes = length / 5 * math.pi * (20**2 - 15**2) / (1000 * v) / f
    result = turn(taper, Blank(40, 100), SHARP)
    assert result.cycle_time == pytest.approx(minutes * 60 + _rapids(taper, SHARP) + CHANGE, rel=1e-6)
    # a quarter circle R10 from Ø20 at Z0 to Ø40 at Z−10: the same integral summed over fine chords
    arc = "G95\nG96 V150 T0101 M4\nG92 S4000\nG0 X20 Z0\nG3 X40 Z-10 R10 F0.2\nG0 X100 Z100\nM30\n"
    moves = [c for c in run(arc, "traub-tx8d", RunSetup(tools=SHARP)).commands if isinstance(c, Move)]
    (quarter,) = [m for m in moves if m.kind == "arc"]
    pts = quarter.points(1e-5)
    want = sum(
        math.dist(a, b) * 2 * math.pi * (a[0] + b[0]) / 2 / (1000 * v * f) for a, b in itertools.pairwise(pts)
    )
    result = turn(arc, Blank(40, 100), SHARP)
    assert result.cycle_time == pytest.approx(want * 60 + _rapids(arc, SHARP) + CHANGE, rel=1e-4)


def test_a_runaway_program_stops_at_the_work_limit() -> None:
    from core.sim.turning import LatheLimits

    program = "G95\nG97 S1000 T0101 M4 F0.2\nG0 X40 Z0\n" + "G2 X40 Z-90 R46\nG3 X40 Z0 R46\n" * 10 + "M30\n"
    toolpath = run(program, "traub-tx8d", RunSetup(tools=OUTSIDE))
    result = simulate_turning(toolpath, Blank(100, 100), OUTSIDE, limits=LatheLimits(max_updates=200_000))
    assert not result.complete
    assert [e.code for e in result.events][-1] == "SIM-E010"
    assert simulate_turning(toolpath, Blank(100, 100), OUTSIDE).complete


def test_revolved_mesh_keeps_to_the_triangle_budget() -> None:
    program = (SEEDS / "tx-30-g71-g88.nc").read_text(encoding="utf-8")
    result = simulate_turning(run(program, "traub-tx8d"), Blank(100, 160))
    full = revolved_mesh(result.profile)[1]
    small = revolved_mesh(result.profile, max_triangles=5_000)[1]
    assert len(small) <= 5_000 < len(full)
    assert _closed(small)


def test_cycle_time_facing_past_the_centre_runs_at_the_limit() -> None:
    to_centre = "G95\nG96 V200 T0101 M4\nG92 S2000\nG0 X42 Z-1\nG1 X0 F0.1\nG0 Z2\nM30\n"
    past = to_centre.replace("G1 X0", "G1 X-2")  # 1 mm further at 2000 1/min and 0.1 mm: 0.3 s
    a = turn(to_centre, Blank(40, 100), SHARP).cycle_time - _rapids(to_centre, SHARP)
    b = turn(past, Blank(40, 100), SHARP).cycle_time - _rapids(past, SHARP)
    assert b - a == pytest.approx(1 / (0.1 * 2000) * 60, rel=1e-6)


# --- rapids that leave a shoulder are no collision; rapids into the part are ------------------------------

TX31_TOOLS = table(
    "tools: [{number: 2, kind: turning, diameter: 1.6, nose_radius: 0.8, quadrant: 4, insert: C}, "
    "{number: 4, kind: turning, diameter: 0.8, nose_radius: 0.4, quadrant: 4, insert: C}]"
)
C08 = table("tools: [{number: 1, kind: turning, diameter: 1.6, nose_radius: 0.8, quadrant: 1, insert: C}]")


def test_g71_roughing_has_no_rapid_into_material() -> None:
    # every pass ends at a shoulder and lifts straight out: the 93° edge slides along the 3° face it has just
    # cut, which is no rapid into the material. TX-17's contour roughed with G71 D3 and a C insert R0.8:
    g71 = (
        "G95\nG96 V180 T0101 M4\nG92 S3000\nG0 X64 Z2\nG71 P10 Q20 I0.5 K0.1 D3 F0.3\nG0 X100 Z50\n"
        "N10 G46\nG0 X16 Z2\nG1 X20 Z0 F0.15\nG1 Z-15\nG2 X40 Z-25 R10\nG1 Z-40\nG3 X60 Z-50 R10\nG1 Z-75\n"
        "G1 X64 Z-77\nN20 G40\nG0 X100 Z50\nM30\n"
    )
    assert events(turn(g71, Blank(62, 120, chuck_length=30), C08)) == []
    # the manual's TX-31 (G89, inside) in a tube Ø130 × 100 with a Ø28 bore: its roughing has no event at all
    program = (SEEDS / "tx-31-g71-g89.nc").read_text(encoding="utf-8")
    result = simulate_turning(
        run(program, "traub-tx8d", RunSetup(tools=TX31_TOOLS)),
        Blank(130, 100, bore=28, chuck_length=20),
        TX31_TOOLS,
    )
    assert [e for e in events(result) if e[1] <= 5] == []
    assert result.removed_volume > 200_000


def test_g72_facing_retracts_are_no_rapid_into_material() -> None:
    # each facing pass ends above the contour and backs off along +Z over the 7° minor edge it has just cut
    g72 = (
        "G95\nG96 V180 T0101 M4\nG92 S3000\nG0 X84 Z1\nG72 P70 Q80 I0.1 K0.3 D2 F0.3\nG0 X100 Z50\n"
        "N70 G46\nG0 X84 Z-20\nG1 X50 F0.15\nG1 Z-10\nG1 X30 Z0\nG1 Z1\nN80 G40\nG0 X100 Z50\nM30\n"
    )
    result = turn(g72, Blank(80, 80, chuck_length=20), C08)
    assert [e for e in events(result) if e[0] == "SIM-E001"] == []
    assert result.removed_volume > 10_000


@pytest.mark.parametrize(
    "block,line",
    [
        ("G0 X30 Z-5", 4),  # diagonally into the bar
        ("G0 Z-10\nG0 X34", 5),  # radially down from above the bar
        ("G0 X36 Z-1", 4),  # 1 mm into the front face
    ],
)
def test_a_rapid_into_the_part_is_still_one(block: str, line: int) -> None:
    program = f"G95\nG97 S1000 T0101 M4\nG0 X42 Z2\n{block}\nG0 X100 Z100\nM30\n"
    result = turn(program, Blank(40, 100), C08)
    assert ("SIM-E001", line) in events(result)


def test_a_rapid_into_the_shoulder_after_a_pass_is_one() -> None:
    # the pass ends at Z−20 before a shoulder; a rapid 1 mm further towards the chuck runs into its face
    program = "G95\nG97 S1000 T0101 M4\nG0 X34 Z2\nG1 Z-20 F0.2\nG0 Z-21\nG0 X100 Z100\nM30\n"
    assert ("SIM-E001", 5) in events(turn(program, Blank(40, 100), C08))
    lift = program.replace("G0 Z-21\n", "G0 X36\n")  # the same pass lifting straight out: no collision
    assert events(turn(lift, Blank(40, 100), C08)) == []


def test_finishing_a_shoulder_after_roughing_measures_only_the_material_it_takes() -> None:
    # four roughing passes end at Z−14.95 (the 93° edge leaves a thin wall over an empty gap at the shoulder);
    # the V finishing tool faces up the shoulder and rounds its edge R3: the deepest chip is 3 mm, within the
    # insert's 4 mm; the gap below the wall was empty and is no depth of cut
    tools = table(
        "tools: [{number: 1, kind: turning, diameter: 1.6, nose_radius: 0.8, quadrant: 1, insert: C}, "
        "{number: 5, kind: turning, diameter: 0.8, nose_radius: 0.4, quadrant: 1, insert: V}]"
    )
    passes = "".join(f"G0 X{x}\nG1 Z-14.95\nG0 X{x + 2}\nG0 Z2\n" for x in (52, 44, 36))
    program = (
        f"G95\nG97 S1000 T0101 M4\nG0 X60 Z2\nG1 Z-14.95 F0.3\nG0 X62\nG0 Z2\n{passes}G0 X100 Z50\n"
        "G97 S1500 T0505 M4\nG0 X30 Z2\nG1 Z-15 F0.15\nG1 X54\nG2 X60 Z-18 R3\nG1 Z-25\nG1 X64\n"
        "G0 X100 Z50\nM30\n"
    )
    result = turn(program, Blank(60, 100), tools)
    assert events(result) == []
    deep = program.replace(
        "G1 X54\nG2 X60 Z-18 R3\n", "G1 X48\nG2 X60 Z-21 R6\n"
    )  # a 6 mm fillet is too deep
    assert [code for code, _ in events(turn(deep, Blank(60, 100), tools))] == ["SIM-E013"]


def test_threading_tool_cutting_towards_the_face_is_against_its_direction() -> None:
    # a P1 thread insert cuts towards the chuck (−Z); the same feed towards +Z is the wrong direction
    tools = table(
        "tools: [{number: 8, kind: turning, diameter: 0.2, nose_radius: 0.1, quadrant: 1, insert: thread}, "
        "{number: 1, kind: turning, diameter: 1.6, nose_radius: 0.8, quadrant: 1, insert: C}]"
    )
    pre = "G95\nG97 S800 T0101 M4\nG0 X36 Z2\nG1 Z-40 F0.2\nG1 X42\nG0 X100 Z100\nG97 S500 T0808 M3\n"
    backwards = pre + "G0 X36 Z-35\nG1 X35 Z-5 F1.5\nG0 X42\nG0 X100 Z100\nM30\n"
    assert events(turn(backwards, Blank(40, 100), tools)) == [("SIM-E014", 9)]
    forwards = pre + "G0 X36 Z2\nG1 X35 Z-30 F1.5\nG0 X42\nG0 X100 Z100\nM30\n"
    assert events(turn(forwards, Blank(40, 100), tools)) == []


def test_the_jaws_reach_out_to_their_diameter() -> None:
    # Ø40 × 60, 20 mm in the chuck: a rapid at Ø56 over the clamped length clears jaws of Ø50, not the default
    # jaws (Ø40 + 40 mm)
    program = "G95\nG97 S800 T0101 M4\nG0 X56 Z2\nG0 Z-50\nG0 X56 Z2\nG0 X100 Z100\nM30\n"
    assert events(turn(program, Blank(40, 60, chuck_length=20, jaw_diameter=50), C08)) == []
    assert events(turn(program, Blank(40, 60, chuck_length=20), C08))[0] == ("SIM-E012", 4)


def test_default_resolution_holds_exam_tolerances() -> None:
    # 0.05 mm along Z by default, radii exact: Ø30.02 is 30.02 (within 0.01 mm), the shoulder at Z−19.97
    program = "G95\nG97 S1000 T0101 M4\nG0 X42 Z2\nG1 X30.02 F0.2\nG1 Z-19.97\nG1 X42\nG0 X100 Z100\nM30\n"
    result = simulate_turning(run(program, "traub-tx8d", RunSetup(tools=SHARP)), Blank(40, 100), SHARP)
    assert result.resolution <= 0.05
    p = result.profile
    turned = p.zs[np.abs(2 * p.outer - 30.02) <= 0.01]
    assert turned.max() == pytest.approx(0, abs=0.05) and turned.min() == pytest.approx(-19.97, abs=0.05)
    assert 2 * p.outer[np.searchsorted(p.zs, -20.05)] == pytest.approx(40.0)


def test_cli_blank_with_chuck_and_jaw_diameter(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    nc = tmp_path / "rohr.nc"
    nc.write_text(
        "G95\nG97 S800 T0101 M4\nG0 X56 Z2\nG0 Z-50\nG0 X56 Z2\nG0 X100 Z100\nM30\n", encoding="utf-8"
    )
    assert (
        main(["simulate", str(nc), "--dialect", "traub-tx8d", "--blank", "tube:40,20,60,20,50", "--json"])
        == 0
    )
    out = json.loads(capsys.readouterr().out)
    assert out["blank"] == {
        "diameter": 40.0,
        "bore": 20.0,
        "length": 60.0,
        "clamp": 20.0,
        "jaw_diameter": 50.0,
    }
    assert out["events"] == []
    assert main(["simulate", str(nc), "--dialect", "traub-tx8d", "--blank", "bar:40,60,20", "--json"]) == 1
    assert [e["code"] for e in json.loads(capsys.readouterr().out)["events"]] == ["SIM-E012", "SIM-E012"]
    assert (
        main(["simulate", str(nc), "--dialect", "traub-tx8d", "--blank", "bar:40,60,20,30"]) == 2
    )  # jaws < Ø40


def test_the_manuals_most_complete_turning_program_simulates_at_full_resolution() -> None:
    # bench/simulate.py times TX-30 (G71 roughing and SRK finishing of the whole shaft; the Musterprogramm 4711
    # of TX-01 is not in the manual) against 300 ms; here what the run makes
    from bench.simulate import TURN_BLANK, TURN_TOOLS

    toolpath = run(
        (SEEDS / "tx-30-g71-g88.nc").read_text(encoding="utf-8"), "traub-tx8d", RunSetup(tools=TURN_TOOLS)
    )
    result = simulate_turning(toolpath, TURN_BLANK, TURN_TOOLS)
    assert result.resolution == 0.05 and result.removed_volume > 500_000


def _pixels(png: bytes) -> np.ndarray:
    """RGB rows of the half-section PNG (one IDAT, filter 0 on every row, as lathe_export writes it)."""
    import zlib

    width, height = struct.unpack(">II", png[16:24])
    start = png.index(b"IDAT") + 4
    length = struct.unpack(">I", png[start - 8 : start - 4])[0]
    raw = np.frombuffer(zlib.decompress(png[start : start + length]), dtype=np.uint8).reshape(
        height, 1 + 3 * width
    )
    assert not raw[:, 0].any()
    return raw[:, 1:].reshape(height, width, 3)


def test_half_section_png_shows_the_cut_open_tube() -> None:
    # a tube Ø40/Ø20 turned to Ø30 over 20 mm: above the axis the section (material between the bore and the
    # outside, the turned-off ring in the blank's colour), below it the view of the part (the bore hidden)
    from core.sim.lathe_export import BLANK, MATERIAL, VIEW

    blank = Blank(40, 100, bore=20)
    png = half_section_png(turn(CYLINDER, blank, OUTSIDE).profile, blank)
    img = _pixels(png)
    width = img.shape[1]
    scale = width / (blank.length + 10.0)  # pixels per mm (lathe_export's frame: 5 mm margins)
    jaw_r = blank.jaw_radius

    def at(z: float, x: float) -> tuple[int, ...]:
        return tuple(
            int(v) for v in img[int((jaw_r + 5.0 - x) * scale), int((z + blank.length + 5.0) * scale)]
        )

    assert at(-10, 12.5) == MATERIAL and at(-10, 17.5) == BLANK and at(-10, 5) == (255, 255, 255)  # the bore
    assert at(-10, -12.5) == VIEW and at(-10, -5) == VIEW and at(-10, -17.5) == BLANK
    assert at(-50, 17.5) == MATERIAL and at(-50, -17.5) == VIEW  # behind the shoulder the blank's Ø40


def test_boring_passes_retract_from_their_shoulder_without_a_collision() -> None:
    # inside the same as outside: three passes of a boring bar (P4) end at Z−20 and lift 0.5 mm towards the
    # axis; a rapid along the bore at a larger diameter is a collision
    bar = table(
        "tools: [{number: 9, kind: turning, diameter: 1.6, nose_radius: 0.8, quadrant: 4, insert: C}]"
    )
    passes = "".join(f"G0 X{x}\nG1 Z-20 F0.2\nG0 X{x - 1}\nG0 Z2\n" for x in (24, 28, 32))
    program = "G95\nG97 S1000 T0909 M4\nG0 X20 Z2\n" + passes + "G0 X100 Z100\nM30\n"
    assert events(turn(program, Blank(60, 100, bore=20), bar)) == []
    crash = "G95\nG97 S1000 T0909 M4\nG0 X24 Z2\nG0 Z-10\nG0 Z2\nG0 X100 Z100\nM30\n"
    assert events(turn(crash, Blank(60, 100, bore=20), bar)) == [("SIM-E001", 4)]
