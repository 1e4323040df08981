"""The request and response bodies of the API (pydantic); the OpenAPI document is made from these."""

from __future__ import annotations

import math
import re
from datetime import UTC, datetime
from typing import Annotated, Any, Literal, get_args

from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    SerializerFunctionWrapHandler,
    StringConstraints,
    model_serializer,
    model_validator,
    with_config,
)
from pydantic_core import PydanticCustomError

from core.exercises import CriterionId
from core.pipeline import DEFAULT_DIALECT
from core.toolpath import MoveJson
from core.tools import ToolKind
from server.security import PASSWORD_MAX, PASSWORD_MIN, password_problem


def utc(value: datetime) -> datetime:
    """SQLite returns times without their zone; every stored time is UTC."""
    return value.replace(tzinfo=UTC) if value.tzinfo is None else value


Time = Annotated[datetime, AfterValidator(utc)]

# --- text and JSON we store or look up -------------------------------------------------------
# Every string that reaches the database (or a query) goes through clean_text: PostgreSQL text cannot
# hold NUL, and a lone surrogate ("\ud800", valid in JSON, not in UTF-8) cannot be encoded at all.

DB_INT_MAX = 2**31 - 1  # the largest id both databases' INTEGER columns hold
JSON_MAX_DEPTH = 32  # nesting of free-form JSON we store (rubric notes, …)
JSON_MAX_ITEMS = 10_000  # strings, numbers, keys … in one free-form JSON value


def clean_text(value: str) -> str:
    """`value` if it can be stored and looked up on SQLite and PostgreSQL; ValueError otherwise."""
    if "\x00" in value:
        raise ValueError("contains the NUL character / enthält das Zeichen NUL")
    try:
        value.encode("utf-8")
    except UnicodeEncodeError as err:
        raise ValueError(
            "is not valid Unicode (lone surrogate) / ist kein gültiges Unicode (einzelnes Surrogat)"
        ) from err
    return value


def length(max_length: int, min_length: int = 0, pattern: str | None = None) -> StringConstraints:
    """The limits of a text we store: Annotated[str, length(n), CLEAN] is a clean, length-limited text."""
    return StringConstraints(min_length=min_length, max_length=max_length, pattern=pattern)


CLEAN = AfterValidator(clean_text)  # see clean_text


StoredText = Annotated[str, length(200_000), CLEAN]  # long texts (reference programs, task descriptions)
Name = Annotated[str, length(80, min_length=1), CLEAN]
Slug = Annotated[str, length(80, min_length=1), CLEAN]  # looked up: an exercise's slug
Dialect = Annotated[str, length(40, min_length=1), CLEAN]
# a program to check or submit: the body limit bounds it; settings.max_program_chars answers 413 above its own limit
Program = Annotated[str, length(1_000_000), CLEAN]
Username = Annotated[
    str, length(80, min_length=1), CLEAN
]  # a name looked up (login, members): also the names launches made

# "lti" and a digit begins the names of accounts an LTI launch makes (lti<platform>-…, server/lti/launch.py): no
# one else may take such a name, so that no local account looks like one a platform user is meant to get
_LTI_NAME = re.compile(r"lti[0-9]", re.IGNORECASE)
LTI_NAME_DE = "Namen, die mit »lti« und einer Ziffer beginnen, sind Konten aus Lernplattformen vorbehalten"
LTI_NAME_EN = "names starting with 'lti' and a digit are reserved for accounts from learning platforms"


def lti_reserved(name: str) -> bool:
    return _LTI_NAME.match(name) is not None


def _not_lti_name(name: str) -> str:
    if lti_reserved(name):
        raise ValueError(f"{LTI_NAME_DE} / {LTI_NAME_EN}")
    return name


NewUsername = Annotated[
    Annotated[str, length(80, min_length=1, pattern=r"^[A-Za-z0-9_.@-]+$"), CLEAN],
    AfterValidator(_not_lti_name),
]
Password = Annotated[str, length(1000, min_length=1), CLEAN]


def _password_rule(password: str) -> str:
    problem = password_problem(password)
    if problem is not None:
        raise ValueError(f"{problem[0]} / {problem[1]}")
    return password


# a password someone chooses: the one rule of server/security.py (password_problem)
NewPassword = Annotated[
    str,
    AfterValidator(_password_rule),
    AfterValidator(clean_text),
    Field(json_schema_extra={"minLength": PASSWORD_MIN, "maxLength": PASSWORD_MAX}),
]
NewSlug = Annotated[str, length(80, min_length=1, pattern=r"^[a-z0-9][a-z0-9-]*$"), CLEAN]
Title = Annotated[str, length(200, min_length=1), CLEAN]
Subtitle = Annotated[str, length(200), CLEAN]
TaskText = Annotated[str, length(50_000), CLEAN]
ShortText = Annotated[str, length(80), CLEAN]
ExternalUser = Annotated[str, length(200), CLEAN]


def clean_json(value: Any) -> Any:
    """Free-form JSON we store: every key and string clean, finite numbers, bounded depth and size."""
    count = 0
    stack: list[tuple[Any, int]] = [(value, 1)]
    while stack:
        item, depth = stack.pop()
        count += 1
        if count > JSON_MAX_ITEMS:
            raise ValueError(
                f"has more than {JSON_MAX_ITEMS} entries / hat mehr als {JSON_MAX_ITEMS} Einträge"
            )
        if isinstance(item, str):
            clean_text(item)
        elif isinstance(item, float) and not math.isfinite(item):
            raise ValueError("contains a number that is not finite / enthält eine nicht endliche Zahl")
        elif isinstance(item, dict | list):
            if depth > JSON_MAX_DEPTH:
                raise ValueError(
                    f"is nested deeper than {JSON_MAX_DEPTH} / ist tiefer als {JSON_MAX_DEPTH} verschachtelt"
                )
            children = [*item.keys(), *item.values()] if isinstance(item, dict) else item
            stack.extend((child, depth + 1) for child in children)
    return value


StoredJson = Annotated[dict[str, Any], AfterValidator(clean_json)]

# --- pipeline --------------------------------------------------------------------------------


class ToolSpec(BaseModel):
    number: int = Field(ge=1, le=99)
    diameter: float = Field(gt=0, le=1000, description="mm")
    kind: ToolKind = Field(default="end_mill", description="every kind of docs/tools.md")
    name: ShortText = ""
    nose_radius: float = Field(default=0.0, ge=0, le=50, description="turning: nose radius R_s in mm")
    quadrant: int = Field(
        default=0, ge=0, le=4, description="turning: cutting-edge quadrant P1…P4 (0: not given)"
    )


class ProgramRequest(BaseModel):
    model_config = ConfigDict(extra="forbid")

    program: Program = Field(description="The NC program text")
    dialect: Dialect = Field(default=DEFAULT_DIALECT, description="e.g. pal-mill")
    exercise: Slug | None = Field(
        default=None, description="Slug of an exercise whose tool table and stock to use"
    )
    tools: list[ToolSpec] | None = Field(
        default=None, max_length=99, description="Tools that override the default table (free practice)"
    )
    skip_blocks: bool | None = Field(
        default=None,
        description="Skip blocks marked with /; not given: the "
        "dialect's default (PAL runs them, TRAUB skips them)",
    )


Coordinate = Annotated[float, Field(allow_inf_nan=False)]


class StockSpec(BaseModel):
    """A box of stock between two corners, workpiece coordinates in mm."""

    model_config = ConfigDict(extra="forbid")

    min: list[Coordinate] = Field(min_length=3, max_length=3, description="[x0, y0, z0]")
    max: list[Coordinate] = Field(min_length=3, max_length=3, description="[x1, y1, z1]")


class BlankSpec(BaseModel):
    """Turning: a bar (inner diameter 0) or tube, its face at Z0, the bar towards −Z (mm)."""

    model_config = ConfigDict(extra="forbid")

    diameter: float = Field(gt=0, le=2000)
    inner_diameter: float = Field(default=0.0, ge=0, le=2000, description="0: a bar")
    length: float = Field(gt=0, le=5000)
    chuck_length: float | None = Field(
        default=None, gt=0, le=5000, description="Clamped length; default a third of the length, ≤ 30 mm"
    )

    @model_validator(mode="after")
    def _sizes(self) -> BlankSpec:
        if self.inner_diameter >= self.diameter:
            raise ValueError("inner_diameter must be less than diameter")
        if self.chuck_length is not None and self.chuck_length >= self.length:
            raise ValueError("chuck_length must be less than length")
        return self


class SimulateRequest(ProgramRequest):
    stock: StockSpec | None = Field(
        default=None,
        description="Default: the exercise's stock, else the PAL "
        "examples' block 80 × 70 × 30 ([0,0,-30]–[80,70,0])",
    )
    blank: BlankSpec | None = Field(
        default=None,
        description="Turning (TRAUB): the bar or tube; default: the "
        "exercise's blank, else a bar around the program",
    )
    resolution: float = Field(default=0.1, ge=0.05, le=5.0, description="Cell size of the height map, mm")


class DiagnosticOut(BaseModel):
    model_config = ConfigDict(extra="allow")  # the pipeline may add fields

    code: str
    severity: Literal["error", "warning", "info"]
    line: int
    column: int
    end_line: int
    end_column: int
    message: str
    message_en: str


class CheckResponse(BaseModel):
    model_config = ConfigDict(extra="allow")

    diagnostics: list[DiagnosticOut]


@with_config(ConfigDict(extra="allow"))  # the pipeline may add fields
class MoveOut(MoveJson):
    """A move: core/toolpath.py's MoveJson, the one definition of its fields (Move.to_json makes it)."""


class DwellOut(BaseModel):
    model_config = ConfigDict(extra="allow")  # the pipeline may add fields

    line: int
    position: list[float]
    seconds: float


class ToolChangeOut(BaseModel):
    model_config = ConfigDict(extra="allow")  # the pipeline may add fields

    line: int
    tool: int | None
    tc: int
    tr: float
    tl: float
    position: list[float]


class FinalOut(BaseModel):
    model_config = ConfigDict(extra="allow")  # the pipeline may add fields

    position: list[float]


class RunResponse(BaseModel):
    """The shape of `paltrainer run --json`."""

    model_config = ConfigDict(extra="allow")

    moves: list[MoveOut]
    dwells: list[DwellOut]
    tool_changes: list[ToolChangeOut]
    diagnostics: list[DiagnosticOut]
    final: FinalOut


class SimulateResponse(BaseModel):
    """The shape of `paltrainer simulate --json`."""

    model_config = ConfigDict(extra="allow")

    removed_volume_mm3: float
    remaining_volume_mm3: float
    cycle_time_s: float
    resolution_mm: float
    events: list[dict[str, Any]]


class Health(BaseModel):
    status: Literal["ok"]


class Ready(BaseModel):
    status: Literal["ready"]
    database: Literal["ok"]
    workers: Literal["ok"]


# --- accounts --------------------------------------------------------------------------------

Role = Literal["student", "instructor", "admin"]
Scope = Literal["practice", "exercises:read", "exercises:write", "submissions:read", "submissions:write"]


class Token(BaseModel):
    access_token: str
    token_type: Literal["bearer"] = "bearer"


class LoginRequest(BaseModel):
    username: Username
    password: Password


class UserOut(BaseModel):
    id: int
    username: str
    role: Role
    created_at: Time
    instructor: str | None = Field(default=None, description="The instructor who manages the user (students)")
    active: bool = Field(default=True, description="False: deactivated by an admin (no login, no tokens)")
    must_change_password: bool = Field(
        default=False, description="A one-time password was set: the user must change it before anything else"
    )
    signed_up_to: int | None = Field(
        default=None,
        description="The course whose join code created the account "
        "(self-registration); null: made otherwise",
    )


class Me(BaseModel):
    """Who the request is: a user (session or bearer token) or an API key."""

    kind: Literal["user", "api_key"]
    username: str | None
    role: Role | None
    scopes: list[Scope] | None = Field(description="An API key's scopes; null for users")


ChosenPassword = Annotated[
    str, length(10_000, min_length=1), CLEAN
]  # checked by password_problem in the route: a 422 naming the rule
JoinCodeText = Annotated[str, length(32, min_length=1), CLEAN]


class PasswordChange(BaseModel):
    model_config = ConfigDict(extra="forbid")

    current_password: Password
    new_password: ChosenPassword = Field(description="8 to 1000 characters, not the current one")


class PasswordReset(BaseModel):
    username: str
    password: str = Field(
        description="The one-time password (shown only this once); the user must change it at the next login"
    )


class SignupRequest(BaseModel):
    model_config = ConfigDict(extra="forbid")

    join_code: JoinCodeText
    username: NewUsername
    password: ChosenPassword = Field(description="8 to 1000 characters")


class UserCreate(BaseModel):
    model_config = ConfigDict(extra="forbid")

    username: NewUsername
    password: NewPassword
    role: Role = "student"
    instructor: Username | None = Field(
        default=None,
        description="The instructor who manages the new user; an "
        "instructor creating a student: themselves (also when not given)",
    )


class ApiKeyCreate(BaseModel):
    model_config = ConfigDict(extra="forbid")

    name: Name
    scopes: list[Scope] = Field(min_length=1, max_length=len(get_args(Scope)))


class ApiKeyOut(BaseModel):
    id: int
    name: str
    prefix: str
    scopes: list[Scope]
    owner: str | None
    created_at: Time
    last_used_at: Time | None
    revoked_at: Time | None


class ApiKeyCreated(ApiKeyOut):
    key: str = Field(description="The key itself; shown only this once")


# --- exercises -------------------------------------------------------------------------------


class CriterionSpec(BaseModel):
    """One criterion of the grader (docs/exercises.md)."""

    model_config = ConfigDict(extra="forbid")

    id: CriterionId
    points: int = Field(ge=0, le=100)
    hidden: bool = False
    tolerance: float | None = Field(
        default=None, gt=0, allow_inf_nan=False, description="geometry: mm; technology: relative (0.1 = 10 %)"
    )


class RubricSpec(BaseModel):
    """The grader's criteria (points adding up to 100 make the exercise gradable) and free-form notes."""

    model_config = ConfigDict(extra="allow")

    criteria: list[CriterionSpec] | None = Field(default=None, max_length=20)

    @model_validator(mode="after")
    def _clean_notes(self) -> RubricSpec:
        clean_json(self.model_extra or {})
        return self

    @model_serializer(mode="wrap")
    def _as_given(self, handler: SerializerFunctionWrapHandler) -> dict[str, Any]:
        """Stored as sent: notes without criteria stay without a "criteria" key."""
        data: dict[str, Any] = handler(self)
        if data.get("criteria") is None:
            data.pop("criteria", None)
        return data


class ExerciseFields(BaseModel):
    model_config = ConfigDict(extra="forbid")

    title_de: Title
    title_en: Subtitle = ""
    task_de: TaskText = ""
    task_en: TaskText = ""
    dialect: Dialect = DEFAULT_DIALECT
    stock: StockSpec | None = None
    tools: list[ToolSpec] | None = Field(
        default=None, max_length=99, description="The exercise's whole tool table"
    )
    reference_program: StoredText = ""
    rubric: RubricSpec | None = None
    hidden_criteria: RubricSpec | None = None


Visibility = Literal["draft", "courses", "public"]
_VISIBILITY = (
    "draft: only its author (and admins); courses: also the members of the author's courses; public: "
    "everyone on this server. An exercise set in an assignment is seen by the course's students from its "
    "opening on (docs/server.md)"
)
ExerciseDocumentIn = Annotated[
    dict[str, Any],
    Field(
        description="The whole exercise in the exercise format (docs/exercises.md), as the editor and the YAML import "
        "use it; validated with every error at once (422 EXERCISE_INVALID, details.errors per field)"
    ),
]


class ExerciseCreate(ExerciseFields):
    slug: NewSlug
    visibility: Visibility = Field(default="public", description=_VISIBILITY)
    document: ExerciseDocumentIn | None = None

    @model_validator(mode="before")
    @classmethod
    def _from_document(cls, data: Any) -> Any:
        """With `document` the other fields come from it (the document is validated on its own)."""
        if isinstance(data, dict) and isinstance(data.get("document"), dict):
            doc = data["document"]
            title = doc.get("title") if isinstance(doc.get("title"), dict) else {}
            slug = doc.get("id") if isinstance(doc.get("id"), str) and doc.get("id") else "neu"
            return {
                "document": doc,
                "visibility": data.get("visibility", "draft"),
                "slug": slug[:80],
                "title_de": str(title.get("de") or "-")[:200],
            }
        return data


class ExerciseUpdate(BaseModel):
    model_config = ConfigDict(extra="forbid")

    title_de: Title | None = None
    title_en: Subtitle | None = None
    task_de: TaskText | None = None
    task_en: TaskText | None = None
    dialect: Dialect | None = None
    stock: StockSpec | None = None
    tools: list[ToolSpec] | None = Field(default=None, max_length=99)
    reference_program: StoredText | None = None
    rubric: RubricSpec | None = None
    hidden_criteria: RubricSpec | None = None
    visibility: Visibility | None = Field(default=None, description=_VISIBILITY)
    archived: bool | None = Field(default=None, description="false: back from the archive (true: DELETE)")
    document: ExerciseDocumentIn | None = None


class DrawingPreviewIn(BaseModel):
    model_config = ConfigDict(extra="forbid")

    document: ExerciseDocumentIn
    lang: Literal["de", "en"] = "de"


class TaskPreviewIn(BaseModel):
    model_config = ConfigDict(extra="forbid")

    markdown: TaskText


class TaskPreview(BaseModel):
    html: str = Field(description="The Markdown as the exercise page shows it (safe HTML)")


class ExerciseOut(BaseModel):
    slug: str
    title_de: str
    title_en: str
    task_de: str
    task_en: str
    dialect: str
    stock: dict[str, Any] | None
    tools: list[dict[str, Any]] | None = Field(description="Tool table entries (docs/tools.md)")
    rubric: dict[str, Any] | None = Field(
        description="Without hidden criteria unless one manages the exercise"
    )
    gradable: bool = Field(
        description="Submissions are graded (the exercise is complete in the grader's format)"
    )
    owner: str | None
    builtin: bool
    created_at: Time
    updated_at: Time
    reference_program: str | None = Field(description="Only for the owner and admins; null otherwise")
    hidden_criteria: dict[str, Any] | None = Field(
        description="Only for the owner and admins; null otherwise"
    )
    kind: str = Field(default="write", description="write | complete | fix (docs/exercises.md)")
    start_program: str = Field(
        default="", description="What the trainee starts from (kinds complete and fix)"
    )
    locked_lines: list[int] = Field(
        default=[], description="Lines of start_program that must stay (kind complete)"
    )
    cutting_data: list[dict[str, Any]] = Field(default=[], description="Prescribed S and F per tool")
    order: int | None = Field(
        default=None, description="Place in its set (the list is sorted by it, then title)"
    )
    dialect_title: str = Field(default="", description="The dialect's German name, e.g. PAL Fräsen")
    dialect_title_en: str = Field(default="", description="The dialect's English name, e.g. PAL milling")
    hint_count: int = Field(
        default=0, description="Hints one at a time: GET /exercises/{slug}/hints/{n}, n = 1 …"
    )
    solution: Literal["never", "after_submission", "after_full_marks"] = Field(
        default="after_submission",
        description="When GET /exercises/{slug}/solution shows the reference to students",
    )
    task_html_de: str = Field(
        default="",
        description="task_de as HTML to insert into the page as it is: paragraphs, "
        "bold, italic, lists, inline code, https links; raw HTML in the Markdown is text",
    )
    task_html_en: str = Field(default="", description="task_en (else task_de) as HTML, as task_html_de")
    blank_de: str = Field(
        default="",
        description="The blank, e.g. 'Rohteil: Stange Ø100 × 160 mm, 30 mm im Futter' "
        "or 'Rohteil: 80 × 70 × 30 mm'; empty without a stock",
    )
    blank_en: str = Field(default="", description="The blank in English, e.g. 'Blank: bar Ø100 × 160 mm'")
    zero_de: str = Field(default="", description="'Werkstücknullpunkt: …', where the workpiece zero lies")
    zero_en: str = Field(default="", description="'Workpiece zero: …'")
    blank_in_task_de: bool = Field(
        default=False,
        description="task_de states the blank itself: the page does not "
        "print blank_de above it a second time",
    )
    blank_in_task_en: bool = Field(
        default=False, description="task_en (else task_de) states the blank itself"
    )
    visibility: str = Field(default="public", description=_VISIBILITY)
    version: int = Field(default=1, description="Raised by every edit of the content once published")
    archived: bool = Field(
        default=False, description="Deleted with submissions: hidden, its submissions kept"
    )
    own_drawing: str | None = Field(
        default=None,
        description="The media type of the author's own drawing "
        "(GET …/own-drawing), shown and printed instead of the generated one; null: none",
    )
    document: dict[str, Any] | None = Field(
        default=None,
        description="The whole exercise document (the editor's "
        "model, docs/exercises.md): only for its owner and admins",
    )
    tool_feeds: dict[str, dict[str, Any]] = Field(
        default={},
        description="Turning: per tool number its feeds (mm/U) as F ('feed') and as the reduced feed E "
        "('reduced': what the reference writes as E) and its spindle direction ('spindle': "
        "M3, M4 or null), as the task sheet prints them; {} for milling",
    )


# --- submissions -----------------------------------------------------------------------------


class SubmissionCreate(BaseModel):
    model_config = ConfigDict(extra="forbid")

    exercise: Slug = Field(description="Exercise slug")
    program: Program
    skip_blocks: bool = False
    external_user: ExternalUser | None = Field(
        default=None,
        description="The learner's id on the learning platform (API keys of the operator, an "
        "instructor or an admin only)",
    )
    assignment: int | None = Field(
        default=None,
        ge=1,
        le=DB_INT_MAX,
        description="The assignment it is for (GET /me/assignments); without it, the running exam or the open "
        "practice assignment with the exercise, if any",
    )


class RunSummary(BaseModel):
    moves: int
    rapid: int
    feed: int
    arc: int
    tool_changes: int
    dwells: int


class LmsResult(BaseModel):
    """A grade as a learning platform takes it (Moodle, ILIAS): points, maximum, and a comment for the learner."""

    score: int
    maximum: int
    comment: str = Field(description="German: the criteria that lost points, with their messages")
    comment_en: str


OverrideComment = Annotated[str, length(2000), CLEAN]


class OverrideOut(BaseModel):
    """The teacher's last word on a submission: the score that counts instead of the grader's, and why."""

    score: int
    automatic_score: int | None = Field(description="The grader's score it replaces")
    comment: str
    by: str | None = Field(description="The instructor who set it")
    at: Time
    message: str = Field(
        description='As the trainee reads it: "Punktzahl von der Lehrkraft geändert: 80 statt 50 – …"'
    )
    message_en: str


class OverrideIn(BaseModel):
    model_config = ConfigDict(extra="forbid")

    score: int = Field(ge=0, le=100_000, description="Points, 0 … the grade's max_score")
    comment: OverrideComment = Field(default="", description="Why (shown to the trainee)")


class SubmissionOut(BaseModel):
    id: int
    exercise: str
    exercise_title: str = Field(
        default="", description="The exercise's German title (lists show it, not the slug)"
    )
    exercise_title_en: str = Field(default="", description="The exercise's English title, if it has one")
    user: str | None
    external_user: str | None
    dialect: str
    created_at: Time
    error_count: int | None = Field(
        description="null for its author while held (an exam's, not yet released)"
    )
    warning_count: int | None = Field(description="null for its author while held")
    grading: dict[str, Any] | None = Field(
        description="The grade as `paltrainer grade --json` (hidden criteria only for the exercise's owner and "
        "admins); null if the exercise is not gradable, and for its author while held or while the "
        'exercise is in an unreleased exam of their course (docs/server.md, "Exams")'
    )
    score: int | None = Field(description="Points out of grading.max_score; null if not graded or not shown")
    held: bool = Field(
        default=False,
        description="An exam's submission as its author sees it before the results "
        "are released: stored and handed in, nothing else until then",
    )
    summary: RunSummary | None = Field(description="null for its author while held")
    override: OverrideOut | None = Field(
        default=None, description="The teacher's score and comment, if set; `score` is then this one"
    )
    diagnostics: list[DiagnosticOut] | None = Field(description="The check diagnostics (detail views only)")
    program: str | None = Field(description="The program (detail views only)")
    lms: LmsResult | None = Field(
        default=None, description="The grade for a learning platform; null if not graded"
    )
    exercise_version: int | None = Field(
        default=None, description="The exercise's version it was graded against"
    )
    version_note: str = Field(
        default="", description='"Version 1" when that is not the exercise\'s current one'
    )


# --- the trainee's day: drafts, history, progress, hints, solution (issue 15) ---------------------


class DraftIn(BaseModel):
    model_config = ConfigDict(extra="forbid")

    program: Program = Field(
        description="The editor's text (at most PALTRAINER_MAX_PROGRAM_CHARS characters)"
    )


class DraftOut(BaseModel):
    exercise: str
    assignment: int | None = Field(
        default=None, description="The exam this draft belongs to; null: the practice draft"
    )
    program: str | None = Field(
        description="The saved text; null: no draft (start from the exercise's start_program)"
    )
    updated_at: Time | None


class MySubmission(BaseModel):
    """One of the caller's own submissions, with what "in den Editor laden" needs."""

    id: int
    exercise: str
    created_at: Time
    score: int | None
    max_score: int | None
    error_count: int | None = Field(description="null while held (an exam's, not yet released)")
    warning_count: int | None
    held: bool = False
    override: OverrideOut | None = None
    criteria: list[dict[str, Any]] = Field(
        description="The grade's criteria as the trainee sees them (no hidden "
        "ones; none while held or withheld by an exam)"
    )
    program: str


class Progress(BaseModel):
    """Where the caller stands on one exercise."""

    exercise: str
    status: Literal["not_started", "draft", "submitted"]
    best_score: int | None = Field(
        description="The best score of the caller's submissions; null: none graded"
    )
    max_score: int | None
    best_submission: int | None = Field(
        description="Id of the submission with the best score (the newest of equals)"
    )
    submissions: int
    draft_updated_at: Time | None


class Hint(BaseModel):
    exercise: str
    number: int = Field(description="1 … count")
    count: int
    text: str = Field(description="German")
    text_en: str


class Solution(BaseModel):
    exercise: str
    program: str = Field(description="The reference program")
    dialect: str
    policy: Literal["never", "after_submission", "after_full_marks"]


# --- instructors: their students, class lists, results (issue 15) ---------------------------------


class UserUpdate(BaseModel):
    model_config = ConfigDict(extra="forbid")

    instructor: Username | None = Field(
        default=None,
        description="The instructor who manages the user; null: nobody (left as it is when absent)",
    )
    role: Role | None = Field(default=None, description="The user's new role (absent or null: unchanged)")

    @model_validator(mode="before")
    @classmethod
    def _known_role(cls, data: Any) -> Any:
        role = data.get("role") if isinstance(data, dict) else None
        if role is not None and role not in Role.__args__:  # type: ignore[attr-defined]
            raise PydanticCustomError(
                "role",
                "Rolle »{role}« gibt es nicht (student, instructor oder admin) / no such "
                "role (student, instructor or admin)",
                {"role": str(role)[:40]},
            )
        return data


class ImportedUser(BaseModel):
    username: str
    role: Role
    instructor: str | None
    password: str | None = Field(
        description="The generated password (shown only this once); null when the list gave one"
    )


class ImportedUsers(BaseModel):
    users: list[ImportedUser]


class ResultCell(BaseModel):
    best_score: int | None = Field(description="null: submitted, not graded")
    max_score: int | None
    best_submission: int = Field(description="Id of the best submission: GET /submissions/{id}")
    overridden: bool = Field(default=False, description="Its score was set by an instructor")
    submissions: list[int] = Field(description="Every submission's id, newest first")
    created_at: Time = Field(description="When the best submission was made")
    exercise_version: int | None = Field(
        default=None, description="The version the best submission was graded against"
    )
    version_note: str = Field(
        default="", description='"Version 1" when that is not the exercise\'s current one'
    )


class ResultRow(BaseModel):
    username: str
    instructor: str | None
    results: dict[str, ResultCell] = Field(description="Per exercise slug; exercises not tried are absent")


class ResultExercise(BaseModel):
    slug: str
    title_de: str
    title_en: str


class Results(BaseModel):
    exercises: list[ResultExercise] = Field(
        description="The columns: exercises with a submission, in list order"
    )
    trainees: list[ResultRow] = Field(
        description="The rows: the caller's students and everyone whose "
        "submissions the caller may see, by name"
    )
