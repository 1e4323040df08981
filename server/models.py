"""The database tables (SQLAlchemy 2): users, API keys, exercises, submissions, drafts, courses and assignments.
Migrations: server/migrations."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

from sqlalchemy import (
    JSON,
    DateTime,
    Float,
    ForeignKey,
    Index,
    Integer,
    LargeBinary,
    String,
    Text,
    UniqueConstraint,
)
from sqlalchemy import false as sa_false
from sqlalchemy import text as sa_text
from sqlalchemy.orm import DeclarativeBase, Mapped, mapped_column

ROLES = ("student", "instructor", "admin")
SCOPES = ("practice", "exercises:read", "exercises:write", "submissions:read", "submissions:write")


def now() -> datetime:
    return datetime.now(UTC)


class Base(DeclarativeBase):
    pass


class User(Base):
    __tablename__ = "users"

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    username: Mapped[str] = mapped_column(String(80), unique=True, index=True)
    password_hash: Mapped[str] = mapped_column(String(255))
    role: Mapped[str] = mapped_column(String(20))
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)
    # carried in every token as "ver"; logging out raises it, which revokes every token issued before
    token_version: Mapped[int] = mapped_column(Integer, default=0, server_default="0")
    # the instructor who manages this student: sees their submissions and results (issue 15)
    instructor_id: Mapped[int | None] = mapped_column(
        ForeignKey("users.id", ondelete="SET NULL"), nullable=True, index=True
    )
    # a password set by someone else (an instructor's or admin's reset): changed by its owner at the next login
    must_change_password: Mapped[bool] = mapped_column(default=False, server_default=sa_false())
    deactivated_at: Mapped[datetime | None] = mapped_column(DateTime(timezone=True), nullable=True)
    # the course whose join code created this account (PALTRAINER_SELF_SIGNUP=course-code); None: made otherwise
    signup_course_id: Mapped[int | None] = mapped_column(
        ForeignKey("courses.id", ondelete="SET NULL", name="fk_users_signup_course_id_courses"), nullable=True
    )


class ApiKey(Base):
    """A key for a learning platform: only its hash is stored; `prefix` identifies it in lists and logs."""

    __tablename__ = "api_keys"

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    name: Mapped[str] = mapped_column(String(80))
    prefix: Mapped[str] = mapped_column(String(16), unique=True, index=True)
    key_hash: Mapped[str] = mapped_column(String(64))
    scopes: Mapped[list[str]] = mapped_column(JSON)
    owner_id: Mapped[int | None] = mapped_column(ForeignKey("users.id", ondelete="SET NULL"), nullable=True)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)
    last_used_at: Mapped[datetime | None] = mapped_column(DateTime(timezone=True), nullable=True)
    revoked_at: Mapped[datetime | None] = mapped_column(DateTime(timezone=True), nullable=True)


class Exercise(Base):
    __tablename__ = "exercises"

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    slug: Mapped[str] = mapped_column(String(80), unique=True, index=True)
    title_de: Mapped[str] = mapped_column(String(200))
    title_en: Mapped[str] = mapped_column(String(200), default="")
    task_de: Mapped[str] = mapped_column(Text, default="")
    task_en: Mapped[str] = mapped_column(Text, default="")
    dialect: Mapped[str] = mapped_column(String(40))
    stock: Mapped[dict[str, Any] | None] = mapped_column(JSON, nullable=True)
    tools: Mapped[list[dict[str, Any]] | None] = mapped_column(JSON, nullable=True)
    reference_program: Mapped[str] = mapped_column(Text, default="")
    rubric: Mapped[dict[str, Any] | None] = mapped_column(JSON, nullable=True)
    hidden_criteria: Mapped[dict[str, Any] | None] = mapped_column(JSON, nullable=True)
    # the whole exercise in the format of core.exercises (docs/exercises.md); None: not gradable
    document: Mapped[dict[str, Any] | None] = mapped_column(JSON, nullable=True)
    owner_id: Mapped[int | None] = mapped_column(ForeignKey("users.id", ondelete="SET NULL"), nullable=True)
    builtin: Mapped[bool] = mapped_column(default=False)
    # who sees it: "draft" (its author and admins), "courses" (also the students of the author's courses),
    # "public" (everyone on this server); an exercise set in an assignment follows that assignment's rules
    visibility: Mapped[str] = mapped_column(String(20), default="public", server_default="public")
    version: Mapped[int] = mapped_column(
        Integer, default=1, server_default="1"
    )  # raised by an edit once published
    archived_at: Mapped[datetime | None] = mapped_column(DateTime(timezone=True), nullable=True)  # "deleted"
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)
    updated_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now, onupdate=now)


class ExerciseVersion(Base):
    """An earlier version of an exercise, kept when an edit made a new one: submissions graded against it name
    it (Submission.exercise_version)."""

    __tablename__ = "exercise_versions"
    __table_args__ = (
        UniqueConstraint("exercise_id", "version", name="uq_exercise_versions_exercise_version"),
    )

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    exercise_id: Mapped[int] = mapped_column(ForeignKey("exercises.id", ondelete="CASCADE"), index=True)
    version: Mapped[int] = mapped_column(Integer)
    title_de: Mapped[str] = mapped_column(String(200))
    document: Mapped[dict[str, Any] | None] = mapped_column(JSON, nullable=True)
    created_by: Mapped[int | None] = mapped_column(ForeignKey("users.id", ondelete="SET NULL"), nullable=True)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)


class ExerciseDrawing(Base):
    """An instructor's own drawing of an exercise (PDF, PNG or SVG, sanitised and size-limited): shown to trainees
    and printed on the sheet in place of the generated one."""

    __tablename__ = "exercise_drawings"
    __table_args__ = (UniqueConstraint("exercise_id", name="uq_exercise_drawings_exercise"),)

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    exercise_id: Mapped[int] = mapped_column(ForeignKey("exercises.id", ondelete="CASCADE"))
    media_type: Mapped[str] = mapped_column(String(40))
    filename: Mapped[str] = mapped_column(String(200))
    data: Mapped[bytes] = mapped_column(LargeBinary)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)


class Submission(Base):
    __tablename__ = "submissions"
    # `attempt` counts the submissions to an assignment with a limit: two racing for the last one cannot both stay
    __table_args__ = (
        UniqueConstraint("assignment_id", "user_id", "exercise_id", "attempt", name="uq_submissions_attempt"),
    )

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    exercise_id: Mapped[int] = mapped_column(ForeignKey("exercises.id", ondelete="RESTRICT"), index=True)
    user_id: Mapped[int | None] = mapped_column(
        ForeignKey("users.id", ondelete="SET NULL"), nullable=True, index=True
    )
    api_key_id: Mapped[int | None] = mapped_column(
        ForeignKey("api_keys.id", ondelete="SET NULL"), nullable=True
    )
    external_user: Mapped[str | None] = mapped_column(String(200), nullable=True)
    program: Mapped[str] = mapped_column(Text)
    dialect: Mapped[str] = mapped_column(String(40))
    error_count: Mapped[int] = mapped_column(Integer, default=0)
    warning_count: Mapped[int] = mapped_column(Integer, default=0)
    result: Mapped[dict[str, Any]] = mapped_column(JSON)
    grading: Mapped[dict[str, Any] | None] = mapped_column(JSON, nullable=True)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)
    # "<k|u><api key or user id>:<Idempotency-Key header>": a repeated request returns this submission
    idempotency_key: Mapped[str | None] = mapped_column(String(300), nullable=True, unique=True, index=True)
    # the assignment it was made for (issue 19); late: after the deadline; held: an exam's, hidden from its
    # author until the instructor releases the results; auto: the last draft, submitted at the exam's end
    assignment_id: Mapped[int | None] = mapped_column(
        ForeignKey("assignments.id", ondelete="SET NULL"), nullable=True, index=True
    )
    late: Mapped[bool] = mapped_column(default=False, server_default=sa_false())
    held: Mapped[bool] = mapped_column(default=False, server_default=sa_false())
    auto: Mapped[bool] = mapped_column(default=False, server_default=sa_false())
    # 1 … the assignment's max_submissions where it has a limit (server/access.py), else null
    attempt: Mapped[int | None] = mapped_column(Integer, nullable=True)
    # the exercise's version it was graded against (Exercise.version at the time); None: before versions existed
    exercise_version: Mapped[int | None] = mapped_column(Integer, nullable=True)
    # the teacher's last word (GradeOverride keeps every change): the score that counts instead of the grader's
    override_score: Mapped[int | None] = mapped_column(Integer, nullable=True)
    override_comment: Mapped[str | None] = mapped_column(Text, nullable=True)
    override_by: Mapped[int | None] = mapped_column(
        ForeignKey("users.id", ondelete="SET NULL"), nullable=True
    )
    override_at: Mapped[datetime | None] = mapped_column(DateTime(timezone=True), nullable=True)


class Draft(Base):
    """A trainee's unsubmitted program for one exercise: saved while typing, brought back on the next visit.
    The practice draft has no assignment; an exam's draft belongs to that exam (it never leaves it, and no
    practice draft enters it)."""

    __tablename__ = "drafts"
    __table_args__ = (
        UniqueConstraint(
            "user_id", "exercise_id", "assignment_id", name="uq_drafts_user_exercise_assignment"
        ),
        Index(
            "uq_drafts_practice",
            "user_id",
            "exercise_id",
            unique=True,
            sqlite_where=sa_text("assignment_id IS NULL"),
            postgresql_where=sa_text("assignment_id IS NULL"),
        ),
    )

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    user_id: Mapped[int] = mapped_column(ForeignKey("users.id", ondelete="CASCADE"), index=True)
    exercise_id: Mapped[int] = mapped_column(ForeignKey("exercises.id", ondelete="CASCADE"), index=True)
    assignment_id: Mapped[int | None] = mapped_column(
        ForeignKey("assignments.id", ondelete="CASCADE"), nullable=True
    )
    program: Mapped[str] = mapped_column(Text)
    updated_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)


class GradeOverride(Base):
    """One change of a submission's score by an instructor (or its removal: score null), with who and when."""

    __tablename__ = "grade_overrides"

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    submission_id: Mapped[int] = mapped_column(ForeignKey("submissions.id", ondelete="CASCADE"), index=True)
    score: Mapped[int | None] = mapped_column(Integer, nullable=True)
    comment: Mapped[str] = mapped_column(Text, default="")
    by_user_id: Mapped[int | None] = mapped_column(ForeignKey("users.id", ondelete="SET NULL"), nullable=True)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)


class Course(Base):
    """A class (Klasse): instructors and students (course_members); students join with `join_code`."""

    __tablename__ = "courses"

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    name: Mapped[str] = mapped_column(String(200))
    join_code: Mapped[str] = mapped_column(String(32), unique=True, index=True)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)


class CourseMember(Base):
    __tablename__ = "course_members"
    __table_args__ = (UniqueConstraint("course_id", "user_id", name="uq_course_members_course_user"),)

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    course_id: Mapped[int] = mapped_column(ForeignKey("courses.id", ondelete="CASCADE"), index=True)
    user_id: Mapped[int] = mapped_column(ForeignKey("users.id", ondelete="CASCADE"), index=True)
    role: Mapped[str] = mapped_column(String(20))  # "instructor" or "student"


class Assignment(Base):
    """Exercises (slugs, in order) set for a course: open from `opens_at`; practice until `deadline`, an exam
    from `opens_at` for `duration_minutes` (its deadline is the end)."""

    __tablename__ = "assignments"

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    course_id: Mapped[int] = mapped_column(ForeignKey("courses.id", ondelete="CASCADE"), index=True)
    title: Mapped[str] = mapped_column(String(200))
    exercises: Mapped[list[str]] = mapped_column(JSON)
    mode: Mapped[str] = mapped_column(String(20))  # "practice" or "exam"
    late: Mapped[str] = mapped_column(String(20))  # "accept" or "refuse"
    opens_at: Mapped[datetime] = mapped_column(DateTime(timezone=True))
    deadline: Mapped[datetime] = mapped_column(DateTime(timezone=True))
    duration_minutes: Mapped[int | None] = mapped_column(Integer, nullable=True)
    settings: Mapped[dict[str, Any]] = mapped_column(JSON)
    released_at: Mapped[datetime | None] = mapped_column(DateTime(timezone=True), nullable=True)
    # an exam's drafts were submitted (after its end); finalising again changes nothing
    finalized_at: Mapped[datetime | None] = mapped_column(DateTime(timezone=True), nullable=True)
    # the lease of the one replica that submits the drafts after the end (another takes over once it expired)
    finalizing_until: Mapped[datetime | None] = mapped_column(DateTime(timezone=True), nullable=True)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)


# --- LTI 1.3: platforms, tool keys, launches (server/lti/, migration 0007) -----------------------------------


class LtiPlatform(Base):
    """A learning platform (Moodle, ILIAS …) registered as an LTI 1.3 platform: one (issuer, client id)."""

    __tablename__ = "lti_platforms"
    __table_args__ = (UniqueConstraint("issuer", "client_id", name="uq_lti_platforms_issuer_client"),)

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    issuer: Mapped[str] = mapped_column(String(500), index=True)
    client_id: Mapped[str] = mapped_column(String(255))
    auth_login_url: Mapped[str] = mapped_column(String(1000))  # the platform's OIDC authorization endpoint
    token_url: Mapped[str] = mapped_column(String(1000))  # OAuth 2 token endpoint (AGS/NRPS access tokens)
    jwks_url: Mapped[str] = mapped_column(String(1000))
    name: Mapped[str] = mapped_column(String(200), default="")
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)


class LtiDeployment(Base):
    __tablename__ = "lti_deployments"
    __table_args__ = (
        UniqueConstraint("platform_id", "deployment_id", name="uq_lti_deployments_platform_dep"),
    )

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    platform_id: Mapped[int] = mapped_column(ForeignKey("lti_platforms.id", ondelete="CASCADE"), index=True)
    deployment_id: Mapped[str] = mapped_column(String(255))


class LtiToolKey(Base):
    """Our RSA signing key: the private key encrypted with the server's secret (server/lti/keys.py); the newest
    key without `retired_at` signs, every key without `retired_at` stays published at /lti/jwks."""

    __tablename__ = "lti_tool_keys"

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    kid: Mapped[str] = mapped_column(String(64), unique=True, index=True)
    private_pem_encrypted: Mapped[str] = mapped_column(Text)
    public_jwk: Mapped[dict[str, Any]] = mapped_column(JSON)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)
    retired_at: Mapped[datetime | None] = mapped_column(DateTime(timezone=True), nullable=True)


class LtiUser(Base):
    __tablename__ = "lti_users"
    __table_args__ = (UniqueConstraint("platform_id", "sub", name="uq_lti_users_platform_sub"),)

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    platform_id: Mapped[int] = mapped_column(ForeignKey("lti_platforms.id", ondelete="CASCADE"), index=True)
    sub: Mapped[str] = mapped_column(String(255))
    user_id: Mapped[int] = mapped_column(ForeignKey("users.id", ondelete="CASCADE"), index=True)
    name: Mapped[str] = mapped_column(String(200), default="")  # from the claims of the latest launch
    email: Mapped[str] = mapped_column(String(320), default="")


class LtiContext(Base):
    """A platform's course (the context claim) and our course for it."""

    __tablename__ = "lti_contexts"
    __table_args__ = (UniqueConstraint("platform_id", "context_id", name="uq_lti_contexts_platform_context"),)

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    platform_id: Mapped[int] = mapped_column(ForeignKey("lti_platforms.id", ondelete="CASCADE"), index=True)
    context_id: Mapped[str] = mapped_column(String(255))
    course_id: Mapped[int | None] = mapped_column(
        ForeignKey("courses.id", ondelete="SET NULL"), nullable=True, index=True
    )
    title: Mapped[str] = mapped_column(String(500), default="")
    memberships_url: Mapped[str | None] = mapped_column(String(1000), nullable=True)  # NRPS


class LtiResourceLink(Base):
    """A placement of PAL Trainer in a platform's course: which exercise or assignment, and its AGS line item."""

    __tablename__ = "lti_resource_links"
    __table_args__ = (UniqueConstraint("platform_id", "resource_link_id", name="uq_lti_links_platform_link"),)

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    platform_id: Mapped[int] = mapped_column(ForeignKey("lti_platforms.id", ondelete="CASCADE"), index=True)
    context_pk: Mapped[int | None] = mapped_column(
        ForeignKey("lti_contexts.id", ondelete="SET NULL"), nullable=True, index=True
    )
    resource_link_id: Mapped[str] = mapped_column(String(255))
    title: Mapped[str] = mapped_column(String(500), default="")
    exercise_slug: Mapped[str | None] = mapped_column(String(80), nullable=True)
    assignment_id: Mapped[int | None] = mapped_column(
        ForeignKey("assignments.id", ondelete="SET NULL"), nullable=True
    )
    lineitem_url: Mapped[str | None] = mapped_column(String(1000), nullable=True)
    lineitems_url: Mapped[str | None] = mapped_column(String(1000), nullable=True)
    ags_scopes: Mapped[list[str]] = mapped_column(JSON, default=list)


class LtiLoginState(Base):
    """An OIDC login in progress: `state` is kept here (no cookie: the tool runs in a cross-site iframe)."""

    __tablename__ = "lti_login_states"

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    state: Mapped[str] = mapped_column(String(128), unique=True, index=True)
    nonce: Mapped[str] = mapped_column(String(128))
    platform_id: Mapped[int] = mapped_column(ForeignKey("lti_platforms.id", ondelete="CASCADE"))
    expires_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), index=True)


class LtiNonce(Base):
    """A nonce of an accepted id_token: a second token with it is a replay (kept until the token expired)."""

    __tablename__ = "lti_nonces"
    __table_args__ = (UniqueConstraint("platform_id", "nonce", name="uq_lti_nonces_platform_nonce"),)

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    platform_id: Mapped[int] = mapped_column(ForeignKey("lti_platforms.id", ondelete="CASCADE"))
    nonce: Mapped[str] = mapped_column(String(255))
    expires_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), index=True)


class LtiRegistrationCode(Base):
    """A dynamic registration URL's code that was used: each code registers one platform (migration 0010). Kept
    until the code would have expired anyway."""

    __tablename__ = "lti_registration_codes"
    __table_args__ = (UniqueConstraint("jti", name="uq_lti_registration_codes_jti"),)

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    jti: Mapped[str] = mapped_column(String(64))
    used_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)
    expires_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), index=True)


class LtiLaunch(Base):
    """One accepted launch: who, from which link, to which exercise; `ticket_hash` is the one-time ticket in the
    URL that the page exchanges for its API token. A deep-linking request keeps its return URL and data here."""

    __tablename__ = "lti_launches"

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    platform_id: Mapped[int] = mapped_column(ForeignKey("lti_platforms.id", ondelete="CASCADE"), index=True)
    deployment_id: Mapped[str] = mapped_column(String(255))
    message_type: Mapped[str] = mapped_column(String(64))
    user_id: Mapped[int] = mapped_column(ForeignKey("users.id", ondelete="CASCADE"), index=True)
    lti_user_pk: Mapped[int] = mapped_column(ForeignKey("lti_users.id", ondelete="CASCADE"))
    resource_link_pk: Mapped[int | None] = mapped_column(
        ForeignKey("lti_resource_links.id", ondelete="SET NULL"), nullable=True, index=True
    )
    exercise_slug: Mapped[str | None] = mapped_column(String(80), nullable=True)
    role: Mapped[str] = mapped_column(String(20))
    ticket_hash: Mapped[str] = mapped_column(String(64), unique=True, index=True)
    ticket_expires_at: Mapped[datetime] = mapped_column(DateTime(timezone=True))
    ticket_used_at: Mapped[datetime | None] = mapped_column(DateTime(timezone=True), nullable=True)
    deep_link_return_url: Mapped[str | None] = mapped_column(String(1000), nullable=True)
    deep_link_data: Mapped[str | None] = mapped_column(Text, nullable=True)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now, index=True)


# --- end of LTI 1.3 (F) ----------------------------------------------------------------------------------------


# --- LTI 1.3 Assignment and Grade Services: the score queue (server/lti/ags.py, migration 0008) --------------


class LtiScore(Base):
    """A grade on its way to a platform's line item (AGS): one row per submission, kept until the platform took
    it. `state`: pending (sent by the drainer when `next_attempt_at` is due), sent, failed (given up after
    ags.MAX_ATTEMPTS; an instructor may retry), superseded (a newer submission's row carries the grade)."""

    __tablename__ = "lti_scores"
    __table_args__ = (UniqueConstraint("submission_id", name="uq_lti_scores_submission"),)

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    submission_id: Mapped[int] = mapped_column(ForeignKey("submissions.id", ondelete="CASCADE"))
    platform_id: Mapped[int] = mapped_column(ForeignKey("lti_platforms.id", ondelete="CASCADE"), index=True)
    resource_link_pk: Mapped[int | None] = mapped_column(
        ForeignKey("lti_resource_links.id", ondelete="SET NULL"), nullable=True, index=True
    )
    course_id: Mapped[int | None] = mapped_column(
        ForeignKey("courses.id", ondelete="SET NULL"), nullable=True, index=True
    )
    user_id: Mapped[int | None] = mapped_column(ForeignKey("users.id", ondelete="SET NULL"), nullable=True)
    exercise_slug: Mapped[str] = mapped_column(String(80))
    lineitem_url: Mapped[str] = mapped_column(String(1000))
    lti_sub: Mapped[str] = mapped_column(String(255))  # the platform's user id: the score's userId
    score_given: Mapped[float | None] = mapped_column(Float, nullable=True)  # of 100; None: not graded
    # "Completed"; "InProgress" for an assignment's line item while some of its exercises are not handed in
    activity_progress: Mapped[str] = mapped_column(String(20), default="Completed")
    timestamp: Mapped[datetime] = mapped_column(DateTime(timezone=True))  # the submission's time
    state: Mapped[str] = mapped_column(String(12), default="pending", index=True)
    attempts: Mapped[int] = mapped_column(Integer, default=0)
    next_attempt_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now, index=True)
    last_error: Mapped[str | None] = mapped_column(String(500), nullable=True)
    sent_at: Mapped[datetime | None] = mapped_column(DateTime(timezone=True), nullable=True)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)


# --- end of the LTI score queue (G) ------------------------------------------------------------------------------
