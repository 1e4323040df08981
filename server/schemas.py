"""The request and response bodies of the API (pydantic); the OpenAPI document is made from these."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Annotated, Any, Literal

from pydantic import AfterValidator, BaseModel, ConfigDict, Field

from core.pipeline import DEFAULT_DIALECT


def utc(value: datetime) -> datetime:
    """SQLite returns times without their zone; every stored time is UTC."""
    return value.replace(tzinfo=UTC) if value.tzinfo is None else value


Time = Annotated[datetime, AfterValidator(utc)]

# --- pipeline --------------------------------------------------------------------------------


class ToolSpec(BaseModel):
    number: int = Field(ge=1, le=99)
    diameter: float = Field(gt=0, le=1000, description="mm")
    kind: Literal["end_mill", "slot_drill"] = "end_mill"
    name: str = Field(default="", max_length=80)


class ProgramRequest(BaseModel):
    model_config = ConfigDict(extra="forbid")

    program: str = Field(description="The NC program text")
    dialect: str = Field(default=DEFAULT_DIALECT, description="e.g. pal-mill")
    exercise: str | None = Field(default=None, description="Slug of an exercise whose tool table and stock to use")
    tools: list[ToolSpec] | None = Field(default=None, max_length=99,
                                         description="Tools that override the default table (free practice)")
    skip_blocks: bool = Field(default=False, description="Skip blocks marked with /")


class StockSpec(BaseModel):
    """A box of stock between two corners, workpiece coordinates in mm."""

    model_config = ConfigDict(extra="forbid")

    min: list[float] = Field(min_length=3, max_length=3, description="[x0, y0, z0]")
    max: list[float] = Field(min_length=3, max_length=3, description="[x1, y1, z1]")


class SimulateRequest(ProgramRequest):
    stock: StockSpec | None = Field(default=None, description="Default: the exercise's stock, else the PAL "
                                                               "examples' block 80 × 70 × 30 ([0,0,-30]–[80,70,0])")
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


class MoveOut(BaseModel):
    model_config = ConfigDict(extra="allow")  # the pipeline may add fields

    line: int
    kind: Literal["rapid", "feed", "arc"]
    start: list[float]
    end: list[float]
    center: list[float] | None
    direction: Literal["cw", "ccw"] | None
    radius: float | None
    angle: float | None
    feed: float
    feed_unit: Literal["mm/min", "mm/rev"]
    spindle: float
    spindle_direction: Literal["cw", "ccw"] | None
    coolant: bool
    tool: int | None
    exact_stop: bool


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
    username: str = Field(min_length=1, max_length=80)
    password: str = Field(min_length=1, max_length=1000)


class UserOut(BaseModel):
    id: int
    username: str
    role: Role
    created_at: Time


class Me(BaseModel):
    """Who the request is: a user (session or bearer token) or an API key."""

    kind: Literal["user", "api_key"]
    username: str | None
    role: Role | None
    scopes: list[Scope] | None = Field(description="An API key's scopes; null for users")


class UserCreate(BaseModel):
    model_config = ConfigDict(extra="forbid")

    username: str = Field(min_length=1, max_length=80, pattern=r"^[A-Za-z0-9_.@-]+$")
    password: str = Field(min_length=8, max_length=1000)
    role: Role = "student"


class ApiKeyCreate(BaseModel):
    model_config = ConfigDict(extra="forbid")

    name: str = Field(min_length=1, max_length=80)
    scopes: list[Scope] = Field(min_length=1)


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


class ExerciseFields(BaseModel):
    model_config = ConfigDict(extra="forbid")

    title_de: str = Field(min_length=1, max_length=200)
    title_en: str = Field(default="", max_length=200)
    task_de: str = Field(default="", max_length=50_000)
    task_en: str = Field(default="", max_length=50_000)
    dialect: str = DEFAULT_DIALECT
    stock: dict[str, Any] | None = None
    tools: list[ToolSpec] | None = Field(default=None, description="The exercise's whole tool table")
    reference_program: str = Field(default="", max_length=200_000)
    rubric: dict[str, Any] | None = None
    hidden_criteria: dict[str, Any] | None = None


class ExerciseCreate(ExerciseFields):
    slug: str = Field(min_length=1, max_length=80, pattern=r"^[a-z0-9][a-z0-9-]*$")


class ExerciseUpdate(BaseModel):
    model_config = ConfigDict(extra="forbid")

    title_de: str | None = Field(default=None, min_length=1, max_length=200)
    title_en: str | None = Field(default=None, max_length=200)
    task_de: str | None = Field(default=None, max_length=50_000)
    task_en: str | None = Field(default=None, max_length=50_000)
    dialect: str | None = None
    stock: dict[str, Any] | None = None
    tools: list[ToolSpec] | None = None
    reference_program: str | None = Field(default=None, max_length=200_000)
    rubric: dict[str, Any] | None = None
    hidden_criteria: dict[str, Any] | None = None


class ExerciseOut(BaseModel):
    slug: str
    title_de: str
    title_en: str
    task_de: str
    task_en: str
    dialect: str
    stock: dict[str, Any] | None
    tools: list[dict[str, Any]] | None = Field(description="Tool table entries (docs/tools.md)")
    rubric: dict[str, Any] | None = Field(description="Without hidden criteria unless one manages the exercise")
    gradable: bool = Field(description="Submissions are graded (the exercise is complete in the grader's format)")
    owner: str | None
    builtin: bool
    created_at: Time
    updated_at: Time
    reference_program: str | None = Field(description="Only for the owner and admins; null otherwise")
    hidden_criteria: dict[str, Any] | None = Field(description="Only for the owner and admins; null otherwise")
    kind: str = Field(default="write", description="write | complete | fix (docs/exercises.md)")
    start_program: str = Field(default="", description="What the trainee starts from (kinds complete and fix)")
    locked_lines: list[int] = Field(default=[], description="Lines of start_program that must stay (kind complete)")
    cutting_data: list[dict[str, Any]] = Field(default=[], description="Prescribed S and F per tool")


# --- submissions -----------------------------------------------------------------------------


class SubmissionCreate(BaseModel):
    model_config = ConfigDict(extra="forbid")

    exercise: str = Field(description="Exercise slug")
    program: str
    skip_blocks: bool = False
    external_user: str | None = Field(default=None, max_length=200,
                                      description="The learner's id on the learning platform (API keys only)")


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


class SubmissionOut(BaseModel):
    id: int
    exercise: str
    user: str | None
    external_user: str | None
    dialect: str
    created_at: Time
    error_count: int
    warning_count: int
    grading: dict[str, Any] | None = Field(
        description="The grade as `paltrainer grade --json` (hidden criteria only for the exercise's owner and "
                    "admins); null if the exercise is not gradable")
    score: int | None = Field(description="Points out of grading.max_score; null if not graded")
    summary: RunSummary
    diagnostics: list[DiagnosticOut] | None = Field(description="The check diagnostics (detail views only)")
    program: str | None = Field(description="The program (detail views only)")
    lms: LmsResult | None = Field(default=None, description="The grade for a learning platform; null if not graded")
