"""Exercises: the file format (one YAML file each in exercises/), its validation, and the built-in set.

The format is documented in docs/exercises.md and versioned by `format`. Loading validates the file
(pydantic) and resolves the reference program (inline or a file next to the exercise); reading files
is the only I/O here and happens in `load_exercise`/`builtin_exercises`, never in the grader.
"""

from __future__ import annotations

import contextlib
import importlib.util
from pathlib import Path
from typing import Annotated, Any, Literal

import yaml  # type: ignore[import-untyped, unused-ignore]
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    ValidationInfo,
    field_validator,
    model_validator,
)
from pydantic_core import ErrorDetails, PydanticCustomError

from core.pipeline import DIALECTS
from core.sim.engine import Stock
from core.sim.tooltable import ToolTableError, tools_from_entries
from core.sim.turning import Blank
from core.tools import DEFAULT_TOOLS, ToolTable

FORMAT_VERSION = 1


def _builtin_dir() -> Path:
    """exercises/ next to core/ in a checkout; in an installed wheel the package paltrainer_exercises."""
    checkout = Path(__file__).resolve().parents[1] / "exercises"
    if checkout.is_dir():
        return checkout
    spec = importlib.util.find_spec("paltrainer_exercises")
    locations = list(spec.submodule_search_locations or []) if spec is not None else []
    return Path(locations[0]) if locations else checkout


EXERCISES_DIR = _builtin_dir()

Vec3 = tuple[float, float, float]
LATHE_DIALECTS = tuple(name for name, d in DIALECTS.items() if d.lathe)  # turning: a blank, not a stock box


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
        try:
            Stock(*self.min, *self.max)  # raises ValueError with the reason
        except ValueError as err:
            raise _rule(
                "stock",
                "min und max: endliche Zahlen bis ±100000 mm, max in X, Y und Z größer als min",
                str(err),
            ) from None
        return self

    def stock(self) -> Stock:
        return Stock(*self.min, *self.max)


class BlankSpec(_Model):
    """Turning: the bar (inner diameter 0) or tube, its face at Z0 and the bar towards −Z; the chuck's jaws hold
    its last `chuck_length` mm and reach out to `jaw_diameter` (core.sim.turning.Blank)."""

    diameter: float = Field(gt=0, le=10_000)  # outer diameter (mm)
    inner_diameter: float = Field(default=0.0, ge=0, le=10_000)  # 0: a bar
    length: float = Field(gt=0, le=10_000)
    chuck_length: float | None = Field(default=None, gt=0, le=10_000)  # None: a third of the length, ≤ 30 mm
    jaw_diameter: float | None = Field(default=None, gt=0, le=10_000)  # None: the diameter + 40 mm
    zero: Text = Text(de="Drehmitte auf der Stirnfläche (Z0)", en="centre of the front face (Z0)")

    @model_validator(mode="after")
    def _blank(self) -> BlankSpec:
        try:
            self.blank()  # raises ValueError with the reason
        except ValueError as err:
            raise _rule(
                "blank",
                "Innendurchmesser kleiner als der Durchmesser, Spannlänge kleiner als die Länge, "
                "Backen größer als der Durchmesser",
                str(err),
            ) from None
        return self

    def blank(self) -> Blank:
        return Blank(self.diameter, self.length, self.inner_diameter, self.chuck_length, self.jaw_diameter)

    def box(self) -> dict[str, Any]:
        """The box around the blank, as a `stock` (what milling-only consumers of an exercise read)."""
        r = self.diameter / 2
        return {"min": (-r, -r, -self.length), "max": (r, r, 0.0), "zero": self.zero.model_dump()}


class CuttingData(_Model):
    """What the task prescribes for one tool: spindle speed S (1/min) or, turning under G96, the cutting speed
    V (m/min); feed F (mm/min, turning: mm per revolution); the spindle's direction M3 (clockwise) or M4
    (counter-clockwise; None: the direction the reference program turns it in for this tool). Turning: a tool may
    have several entries (roughing and finishing feeds); a move passes when it matches one of them."""

    tool: int = Field(ge=1, le=999)
    speed: float | None = Field(default=None, gt=0)
    cutting_speed: float | None = Field(default=None, gt=0)
    feed: float = Field(gt=0)
    spindle: Literal["M3", "M4"] | None = None

    @model_validator(mode="after")
    def _one_speed(self) -> CuttingData:
        if (self.speed is None) == (self.cutting_speed is None):
            raise _rule(
                "cutting_data",
                "genau eines von speed (S, 1/min) und cutting_speed (V, m/min) angeben",
                "give exactly one of speed (S, 1/min) and cutting_speed (V, m/min)",
            )
        return self


CriterionId = Literal[
    "geometry",
    "safety",
    "technology",
    "syntax",
    "tool_change",
    "spindle_on",
    "compensation_off",
    "safe_position",
    "program_end",
    "locked_lines",
]


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
    dialect: Literal["pal-mill", "sinumerik-iso", "beckhoff", "traub-tx8d"] = "pal-mill"
    kind: Literal["write", "complete", "fix"] = "write"
    # milling: the box; turning: `blank`, and `stock` is made from it (the box around the bar)
    stock: StockSpec
    blank: Annotated[BlankSpec | None, Field(validate_default=True)] = None
    tools: list[dict[str, Any]]  # entries in the tool-table format of docs/tools.md
    cutting_data: list[CuttingData] = []
    zero_offsets: dict[Literal["G54", "G55", "G56", "G57"], Vec3] = {}
    subprograms: dict[int, str] = {}  # the exercise's program library: L number → text
    reference: str  # the reference program
    # what the trainee starts from (kinds complete and fix)
    start_program: Annotated[str, Field(validate_default=True)] = ""
    locked_lines: list[int] = []  # lines of start_program that must stay as they are (kind complete)
    rubric: tuple[Criterion, ...] = DEFAULT_RUBRIC
    resolution: float = Field(default=0.1, gt=0, le=2)  # mm, the grid the grader compares on
    hints: list[Text] = []  # shown one at a time on request
    # when students may see the reference: never, after their first submission, after one with full marks
    solution: Literal["never", "after_submission", "after_full_marks"] = "after_submission"
    order: int | None = Field(
        default=None, ge=0, le=100_000
    )  # place in its set (the list: by order, then title)
    source: str = ""  # where the task comes from (e.g. the seed example)

    @field_validator("tools")
    @classmethod
    def _tools(cls, value: list[dict[str, Any]]) -> list[dict[str, Any]]:
        try:
            tools_from_entries(list(value))
        except ToolTableError as err:
            raise ValueError(str(err)) from None
        return value

    @model_validator(mode="before")
    @classmethod
    def _stock_of_blank(cls, data: Any) -> Any:
        """A lathe exercise names its blank; its `stock` is the box around it (always made anew, never written).
        A missing or broken blank is reported by the blank's own validation (with every other error at once)."""
        if isinstance(data, dict) and data.get("dialect") in LATHE_DIALECTS:
            raw = data.get("blank")
            try:
                stock = BlankSpec.model_validate(raw).box() if isinstance(raw, dict) else None
            except ValidationError:
                stock = None
            data = {**data, "stock": stock or {"min": (-1, -1, -1), "max": (1, 1, 0)}}
        return data

    # the rules between fields are checked field by field (each with the fields before it), so that an author
    # reads every broken rule at once, not one per try
    @field_validator("blank", mode="after")
    @classmethod
    def _blank_of_dialect(cls, value: BlankSpec | None, info: ValidationInfo) -> BlankSpec | None:
        dialect = info.data.get("dialect")
        if dialect in LATHE_DIALECTS and value is None:
            raise _rule(
                "blank",
                "fehlt (eine Drehaufgabe braucht das Rohteil: Stange oder Rohr)",
                "is missing (a turning exercise needs its blank: a bar or tube)",
            )
        if dialect is not None and dialect not in LATHE_DIALECTS and value is not None:
            raise _rule(
                "blank",
                "nur für Drehaufgaben (dialect: traub-tx8d); Fräsaufgaben haben »stock«",
                "only for turning exercises (dialect: traub-tx8d); milling exercises have 'stock'",
            )
        return value

    @field_validator("title", mode="after")
    @classmethod
    def _titled(cls, value: Text) -> Text:
        if not value.de.strip():
            raise _rule("title.de", "fehlt (der deutsche Titel der Aufgabe)", "is missing (the German title)")
        return value

    @field_validator("reference", mode="after")
    @classmethod
    def _referenced(cls, value: str) -> str:
        if not value.strip():
            raise _rule(
                "reference",
                "fehlt (das Referenzprogramm, gegen das bewertet wird)",
                "is missing (the reference program submissions are graded against)",
            )
        return value

    @field_validator("cutting_data", mode="after")
    @classmethod
    def _cutting_data(cls, value: list[CuttingData], info: ValidationInfo) -> list[CuttingData]:
        directions: dict[int, set[str]] = {}
        for c in value:
            if c.spindle is not None:
                directions.setdefault(c.tool, set()).add(c.spindle)
        if any(len(d) > 1 for d in directions.values()):
            raise _rule(
                "cutting_data",
                "ein Werkzeug hat nur eine Drehrichtung (spindle: M3 oder M4)",
                "a tool has one spindle direction (spindle: M3 or M4)",
            )
        dialect = info.data.get("dialect")
        if (
            dialect is not None
            and dialect not in LATHE_DIALECTS
            and any(c.cutting_speed is not None for c in value)
        ):
            raise _rule(
                "cutting_data",
                "cutting_speed (V) nur für Drehaufgaben; beim Fräsen speed (S)",
                "cutting_speed (V) only for turning exercises; milling gives speed (S)",
            )
        return value

    @field_validator("start_program", mode="after")
    @classmethod
    def _start_of_kind(cls, value: str, info: ValidationInfo) -> str:
        kind = info.data.get("kind")
        if kind is not None and kind != "write" and not value:
            raise _rule(
                "start_program",
                f"fehlt (Art »{kind}« braucht ein Startprogramm)",
                f"is missing (kind '{kind}' needs a start program)",
            )
        return value

    @field_validator("locked_lines", mode="after")
    @classmethod
    def _locked_in_start(cls, value: list[int], info: ValidationInfo) -> list[int]:
        lines = str(info.data.get("start_program") or "").splitlines()
        if any(not 1 <= n <= len(lines) for n in value):
            raise _rule(
                "locked_lines",
                f"eine Zeilennummer steht nicht im Startprogramm (1 bis {len(lines)})",
                f"a line number is not in start_program (1 to {len(lines)})",
            )
        return value

    @field_validator("rubric", mode="after")
    @classmethod
    def _rubric(cls, value: tuple[Criterion, ...]) -> tuple[Criterion, ...]:
        total = sum(c.points for c in value)
        if total != 100:
            raise _rule(
                "rubric",
                f"die Punkte müssen 100 ergeben (sind {total})",
                f"the points must add up to 100 (they are {total})",
            )
        ids = [c.id for c in value]
        if len(set(ids)) != len(ids):
            raise _rule("rubric", "ein Kriterium steht doppelt", "a criterion appears twice")
        return value

    @property
    def lathe(self) -> bool:
        return self.dialect in LATHE_DIALECTS

    def tool_table(self) -> ToolTable:
        return tools_from_entries(list(self.tools)) if self.tools else DEFAULT_TOOLS

    def criterion(self, cid: str) -> Criterion | None:
        return next((c for c in self.rubric if c.id == cid), None)


def _rule(field: str, de: str, en: str) -> PydanticCustomError:
    """A broken rule of the format, with its field and its German and English text (see field_problem)."""
    return PydanticCustomError("exercise_rule", "{field}: {en}", {"field": field, "de": de, "en": en})


class ExerciseError(ValueError):
    """An exercise file that cannot be used. `str()` is German / English (the command line); `message` and
    `message_en` say what is wrong without a heading; `problems` lists the fields: {field, message, message_en}."""

    def __init__(
        self,
        text: str,
        message: str | None = None,
        message_en: str | None = None,
        problems: list[dict[str, str]] | None = None,
    ) -> None:
        super().__init__(text)
        de, _, en = text.partition(" / ")
        self.message = message if message is not None else de.removeprefix("Aufgabe: ")
        self.message_en = message_en if message_en is not None else (en or de).removeprefix("exercise: ")
        self.problems = problems or []


_ID_RULE = (
    "nur Kleinbuchstaben, Ziffern und Bindestrich (2 bis 81 Zeichen, am Anfang kein Bindestrich)",
    "only lower-case letters, digits and hyphens (2 to 81 characters, not starting with a hyphen)",
)
# pydantic's error types in German and English; {…} are filled from the error's context
_MESSAGES: dict[str, tuple[str, str]] = {
    "missing": ("fehlt", "is missing"),
    "extra_forbidden": (
        "gibt es im Aufgabenformat nicht (Tippfehler?)",
        "is not part of the format (a typo?)",
    ),
    "literal_error": ("erlaubt: {expected}", "allowed: {expected}"),
    "enum": ("erlaubt: {expected}", "allowed: {expected}"),
    "string_type": ("muss ein Text sein", "must be a text"),
    "int_type": ("muss eine ganze Zahl sein", "must be a whole number"),
    "int_parsing": ("muss eine ganze Zahl sein", "must be a whole number"),
    "int_from_float": ("muss eine ganze Zahl sein", "must be a whole number"),
    "float_type": ("muss eine Zahl sein", "must be a number"),
    "float_parsing": ("muss eine Zahl sein", "must be a number"),
    "finite_number": ("muss eine endliche Zahl sein", "must be a finite number"),
    "bool_type": ("muss true oder false sein", "must be true or false"),
    "bool_parsing": ("muss true oder false sein", "must be true or false"),
    "list_type": ("muss eine Liste sein", "must be a list"),
    "tuple_type": ("muss eine Liste sein", "must be a list"),
    "dict_type": ("muss eine Zuordnung (Feld: Wert) sein", "must be a mapping (field: value)"),
    "model_type": ("muss eine Zuordnung (Feld: Wert) sein", "must be a mapping (field: value)"),
    "model_attributes_type": ("muss eine Zuordnung (Feld: Wert) sein", "must be a mapping (field: value)"),
    "greater_than": ("muss größer als {gt} sein", "must be greater than {gt}"),
    "greater_than_equal": ("muss mindestens {ge} sein", "must be at least {ge}"),
    "less_than": ("muss kleiner als {lt} sein", "must be less than {lt}"),
    "less_than_equal": ("darf höchstens {le} sein", "must be at most {le}"),
    "too_short": ("braucht mindestens {min_length} Einträge", "needs at least {min_length} entries"),
    "too_long": ("darf höchstens {max_length} Einträge haben", "may have at most {max_length} entries"),
    "string_too_short": ("braucht mindestens {min_length} Zeichen", "needs at least {min_length} characters"),
    "string_too_long": (
        "darf höchstens {max_length} Zeichen haben",
        "may have at most {max_length} characters",
    ),
    "string_pattern_mismatch": (
        "hat nicht die erlaubte Form ({pattern})",
        "does not have the allowed form ({pattern})",
    ),
}
_LISTS = {
    "tools",
    "cutting_data",
    "rubric",
    "hints",
    "locked_lines",
    "min",
    "max",
}  # their entries count from 1


def _german(value: Any) -> Any:
    """A value of an error's context as German text: 0.5 → 0,5, 0.0 → 0, "a or b" → "a oder b"."""
    if isinstance(value, float):
        return f"{value:g}".replace(".", ",")
    if isinstance(value, str):
        return value.replace(" or ", " oder ")
    return value


def field_name(loc: tuple[int | str, ...]) -> str:
    """`cutting_data[1].feed`: a field's path as an author reads it (list entries counted from 1)."""
    out = ""
    for i, part in enumerate(loc):
        if isinstance(part, int) and i and str(loc[i - 1]) in _LISTS:
            out += f"[{part + 1}]"
        else:
            out += f".{part}" if out else str(part)
    return out


def field_problem(error: ErrorDetails) -> dict[str, str]:
    """One validation error as {field, message, message_en}: German first, never pydantic's English text."""
    ctx: dict[str, Any] = dict(error.get("ctx") or {})
    field = field_name(tuple(error["loc"])) or "(Aufgabe)"
    kind = error["type"]
    if kind == "exercise_rule":
        return {"field": ctx["field"], "message": ctx["de"], "message_en": ctx["en"]}
    if kind == "value_error":  # a validator's own text, German / English
        de, _, en = str(ctx.get("error", error["msg"])).partition(" / ")
        return {"field": field, "message": de, "message_en": en or de}
    if kind == "string_pattern_mismatch" and field == "id":
        de, en = _ID_RULE
    else:
        de, en = _MESSAGES.get(kind, ("ungültiger Wert", error["msg"]))
        with contextlib.suppress(
            KeyError, IndexError
        ):  # a message without the context's fields stays as it is
            de, en = de.format(**{k: _german(v) for k, v in ctx.items()}), en.format(**ctx)
    return {"field": field, "message": de, "message_en": en}


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


# libyaml's safe loader where PyYAML has it (ten times as fast: the server reads every built-in exercise at its start),
# else PyYAML's own
_LOADER: Any = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def _check_structure(text: str) -> None:
    """Refuse what would exhaust the loader or what no database can store, from the parser's events, before
    anything is built: building a document recurses once per nesting level, validation walks every alias again,
    and NUL or a lone surrogate ("\\ud800" in a quoted string) cannot be stored."""
    try:
        _walk(text, _LOADER)
    except yaml.YAMLError:
        # libyaml reads ahead and has limits of its own: PyYAML's parser streams, so it says what is wrong as
        # before (our limits first, with their message, or the error with its line and column)
        _walk(text, yaml.SafeLoader)
        raise


def _walk(text: str, loader: Any) -> None:
    depth = aliases = 0
    for event in yaml.parse(text, Loader=loader):
        if isinstance(event, yaml.CollectionStartEvent):
            depth += 1
            if depth > MAX_NESTING:
                raise ExerciseError(
                    f"Aufgabe: tiefer als {MAX_NESTING} Ebenen verschachtelt / "
                    f"exercise: nested deeper than {MAX_NESTING} levels"
                )
        elif isinstance(event, yaml.CollectionEndEvent):
            depth -= 1
        elif isinstance(event, yaml.AliasEvent):
            aliases += 1
            if aliases > MAX_ALIASES:
                raise ExerciseError(
                    f"Aufgabe: mehr als {MAX_ALIASES} Verweise (*) / "
                    f"exercise: more than {MAX_ALIASES} aliases (*)"
                )
        elif isinstance(event, yaml.ScalarEvent) and not _storable(event.value):
            raise ExerciseError(
                f"Aufgabe: Text mit dem Zeichen NUL oder einem einzelnen Surrogat in Zeile "
                f"{event.start_mark.line + 1} / exercise: text with the NUL character or a lone "
                f"surrogate on line {event.start_mark.line + 1}"
            )


def parse_exercise(text: str, folder: Path | None = None) -> Exercise:
    """An exercise from YAML text; `reference_file`/`start_file` are read from `folder`."""
    try:
        _check_structure(text)
        data = yaml.load(text, Loader=_LOADER)  # (a safe loader)
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        where = f" (Zeile {mark.line + 1}, Spalte {mark.column + 1})" if mark is not None else ""
        raise ExerciseError(
            f"Aufgabe: kein gültiges YAML{where} / exercise: not valid YAML ({err})"
        ) from None
    if not isinstance(data, dict):
        raise ExerciseError("Aufgabe: erwartet eine Zuordnung / exercise: expected a mapping")
    for key, target in (("reference_file", "reference"), ("start_file", "start_program")):
        if key in data:
            if folder is None:
                raise ExerciseError(f"Aufgabe: {key} braucht einen Ordner / exercise: {key} needs a folder")
            name = str(data.pop(key))
            path = (folder / name).resolve()
            if folder.resolve() not in path.parents or not path.is_file():
                raise ExerciseError(
                    f"Aufgabe: {key} »{name}« nicht gefunden / exercise: {key} '{name}' not found"
                )
            data[target] = path.read_text(encoding="utf-8")
    try:
        return Exercise.model_validate(data)
    except ValidationError as err:
        problems = [field_problem(e) for e in err.errors()]
        de = "; ".join(f"Feld `{p['field']}`: {p['message']}" for p in problems)
        en = "; ".join(f"field `{p['field']}`: {p['message_en']}" for p in problems)
        raise ExerciseError(f"Aufgabe: {de} / exercise: {en}", de, en, problems) from None


def load_exercise(path: Path) -> Exercise:
    return parse_exercise(path.read_text(encoding="utf-8"), path.parent)


def builtin_exercises(folder: Path = EXERCISES_DIR) -> dict[str, Exercise]:
    """The exercises shipped in exercises/ (every *.yaml file), by id."""
    found: dict[str, Exercise] = {}
    for path in sorted(folder.rglob("*.yaml")):
        exercise = load_exercise(path)
        found[exercise.id] = exercise
    return found
