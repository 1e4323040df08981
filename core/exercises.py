"""Exercises: the file format (one YAML file each in exercises/), its validation, and the built-in set.

The format is documented in docs/exercises.md and versioned by `format`. Loading validates the file
(pydantic) and resolves the reference program (inline or a file next to the exercise); reading files
is the only I/O here and happens in `load_exercise`/`builtin_exercises`, never in the grader.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal

import yaml  # type: ignore[import-untyped, unused-ignore]
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from core.sim.engine import Stock
from core.sim.tooltable import ToolTableError, tools_from_entries
from core.tools import DEFAULT_TOOLS, ToolTable

FORMAT_VERSION = 1
EXERCISES_DIR = Path(__file__).resolve().parents[1] / "exercises"

Vec3 = tuple[float, float, float]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class Text(_Model):
    """A text in German (required: the trainees' language) and English."""

    de: str
    en: str = ""

    def get(self, lang: str) -> str:
        return self.en if lang == "en" and self.en else self.de


class StockSpec(_Model):
    """The blank: a box between two corners in workpiece coordinates (mm)."""

    min: Vec3
    max: Vec3
    zero: Text = Text(de="linke untere Ecke der Oberseite", en="lower left corner of the top face")

    @model_validator(mode="after")
    def _box(self) -> StockSpec:
        Stock(*self.min, *self.max)  # raises ValueError with the reason
        return self

    def stock(self) -> Stock:
        return Stock(*self.min, *self.max)


class CuttingData(_Model):
    """What the task prescribes for one tool: spindle speed S (1/min) and feed F (mm/min)."""

    tool: int = Field(ge=1, le=999)
    speed: float = Field(gt=0)
    feed: float = Field(gt=0)


CriterionId = Literal["geometry", "safety", "technology", "syntax", "tool_change", "spindle_on",
                      "compensation_off", "safe_position", "program_end", "locked_lines"]


class Criterion(_Model):
    id: CriterionId
    points: int = Field(ge=0, le=100)
    hidden: bool = False  # counts, but students do not see it
    tolerance: float | None = Field(default=None, gt=0)  # geometry: mm; technology: relative (0.1 = 10 %)


DEFAULT_RUBRIC: tuple[Criterion, ...] = (
    Criterion(id="geometry", points=50, tolerance=0.05),
    Criterion(id="safety", points=20),
    Criterion(id="technology", points=10, tolerance=0.1),
    Criterion(id="syntax", points=10),
    Criterion(id="tool_change", points=2),
    Criterion(id="spindle_on", points=2),
    Criterion(id="compensation_off", points=2),
    Criterion(id="safe_position", points=2),
    Criterion(id="program_end", points=2),
)


class Exercise(_Model):
    """One exercise, as written in its YAML file."""

    format: Literal[1] = 1  # FORMAT_VERSION
    id: Annotated[str, Field(pattern=r"^[a-z0-9][a-z0-9-]{1,80}$")]
    title: Text
    task: Text  # markdown
    dialect: Literal["pal-mill", "sinumerik-iso", "beckhoff"] = "pal-mill"
    kind: Literal["write", "complete", "fix"] = "write"
    stock: StockSpec
    tools: list[dict[str, Any]]  # entries in the tool-table format of docs/tools.md
    cutting_data: list[CuttingData] = []
    zero_offsets: dict[Literal["G54", "G55", "G56", "G57"], Vec3] = {}
    subprograms: dict[int, str] = {}  # the exercise's program library: L number → text
    reference: str  # the reference program
    start_program: str = ""  # what the trainee starts from (kinds complete and fix)
    locked_lines: list[int] = []  # lines of start_program that must stay as they are (kind complete)
    rubric: tuple[Criterion, ...] = DEFAULT_RUBRIC
    resolution: float = Field(default=0.1, gt=0, le=2)  # mm, the grid the grader compares on
    hints: list[Text] = []
    source: str = ""  # where the task comes from (e.g. the seed example)

    @field_validator("tools")
    @classmethod
    def _tools(cls, value: list[dict[str, Any]]) -> list[dict[str, Any]]:
        try:
            tools_from_entries(list(value))
        except ToolTableError as err:
            raise ValueError(str(err)) from None
        return value

    @model_validator(mode="after")
    def _consistent(self) -> Exercise:
        if sum(c.points for c in self.rubric) != 100:
            raise ValueError("rubric: the points must add up to 100 / die Punkte müssen 100 ergeben")
        ids = [c.id for c in self.rubric]
        if len(set(ids)) != len(ids):
            raise ValueError("rubric: a criterion appears twice / ein Kriterium steht doppelt")
        if self.kind != "write" and not self.start_program:
            raise ValueError(f"kind {self.kind}: start_program is missing / start_program fehlt")
        lines = self.start_program.splitlines()
        if any(not 1 <= n <= len(lines) for n in self.locked_lines):
            raise ValueError("locked_lines: a line number is not in start_program")
        return self

    def tool_table(self) -> ToolTable:
        return tools_from_entries(list(self.tools)) if self.tools else DEFAULT_TOOLS

    def criterion(self, cid: str) -> Criterion | None:
        return next((c for c in self.rubric if c.id == cid), None)


class ExerciseError(ValueError):
    """An exercise file that cannot be used; the message says where, in German and English."""


MAX_NESTING = 32  # levels of lists and mappings in an exercise file (the format needs 4)
MAX_ALIASES = 100  # YAML aliases (*name): each one is a copy that validation walks again


def _storable(value: str) -> bool:
    if "\x00" in value:
        return False
    try:
        value.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def _check_structure(text: str) -> None:
    """Refuse what would exhaust the loader or what no database can store, from the parser's events, before
    anything is built: building a document recurses once per nesting level, validation walks every alias again,
    and NUL or a lone surrogate ("\\ud800" in a quoted string) cannot be stored."""
    depth = aliases = 0
    for event in yaml.parse(text, Loader=yaml.SafeLoader):
        if isinstance(event, yaml.CollectionStartEvent):
            depth += 1
            if depth > MAX_NESTING:
                raise ExerciseError(f"Aufgabe: tiefer als {MAX_NESTING} Ebenen verschachtelt / "
                                    f"exercise: nested deeper than {MAX_NESTING} levels")
        elif isinstance(event, yaml.CollectionEndEvent):
            depth -= 1
        elif isinstance(event, yaml.AliasEvent):
            aliases += 1
            if aliases > MAX_ALIASES:
                raise ExerciseError(f"Aufgabe: mehr als {MAX_ALIASES} Verweise (*) / "
                                    f"exercise: more than {MAX_ALIASES} aliases (*)")
        elif isinstance(event, yaml.ScalarEvent) and not _storable(event.value):
            raise ExerciseError(f"Aufgabe: Text mit dem Zeichen NUL oder einem einzelnen Surrogat in Zeile "
                                f"{event.start_mark.line + 1} / exercise: text with the NUL character or a lone "
                                f"surrogate on line {event.start_mark.line + 1}")


def parse_exercise(text: str, folder: Path | None = None) -> Exercise:
    """An exercise from YAML text; `reference_file`/`start_file` are read from `folder`."""
    try:
        _check_structure(text)
        data = yaml.safe_load(text)
    except yaml.YAMLError as err:
        raise ExerciseError(f"Aufgabe: kein gültiges YAML / exercise: not valid YAML ({err})") from None
    if not isinstance(data, dict):
        raise ExerciseError("Aufgabe: erwartet eine Zuordnung / exercise: expected a mapping")
    for key, target in (("reference_file", "reference"), ("start_file", "start_program")):
        if key in data:
            if folder is None:
                raise ExerciseError(f"Aufgabe: {key} braucht einen Ordner / exercise: {key} needs a folder")
            name = str(data.pop(key))
            path = (folder / name).resolve()
            if folder.resolve() not in path.parents or not path.is_file():
                raise ExerciseError(f"Aufgabe: {key} »{name}« nicht gefunden / exercise: {key} '{name}' not found")
            data[target] = path.read_text(encoding="utf-8")
    try:
        return Exercise.model_validate(data)
    except ValidationError as err:
        problems = "; ".join(f"{'.'.join(str(p) for p in e['loc'])}: {e['msg']}" for e in err.errors())
        raise ExerciseError(f"Aufgabe ungültig / exercise invalid: {problems}") from None


def load_exercise(path: Path) -> Exercise:
    return parse_exercise(path.read_text(encoding="utf-8"), path.parent)


def builtin_exercises(folder: Path = EXERCISES_DIR) -> dict[str, Exercise]:
    """The exercises shipped in exercises/ (every *.yaml file), by id."""
    found: dict[str, Exercise] = {}
    for path in sorted(folder.rglob("*.yaml")):
        exercise = load_exercise(path)
        found[exercise.id] = exercise
    return found
