"""The database tables (SQLAlchemy 2): users, API keys, exercises, submissions, drafts, courses and assignments.
Migrations: server/migrations."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

from sqlalchemy import JSON, DateTime, ForeignKey, Integer, String, Text, UniqueConstraint
from sqlalchemy import false as sa_false
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
    instructor_id: Mapped[int | None] = mapped_column(ForeignKey("users.id", ondelete="SET NULL"), nullable=True,
                                                      index=True)


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
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)
    updated_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now, onupdate=now)


class Submission(Base):
    __tablename__ = "submissions"

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    exercise_id: Mapped[int] = mapped_column(ForeignKey("exercises.id", ondelete="RESTRICT"), index=True)
    user_id: Mapped[int | None] = mapped_column(ForeignKey("users.id", ondelete="SET NULL"), nullable=True,
                                                index=True)
    api_key_id: Mapped[int | None] = mapped_column(ForeignKey("api_keys.id", ondelete="SET NULL"), nullable=True)
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
    assignment_id: Mapped[int | None] = mapped_column(ForeignKey("assignments.id", ondelete="SET NULL"),
                                                      nullable=True, index=True)
    late: Mapped[bool] = mapped_column(default=False, server_default=sa_false())
    held: Mapped[bool] = mapped_column(default=False, server_default=sa_false())
    auto: Mapped[bool] = mapped_column(default=False, server_default=sa_false())


class Draft(Base):
    """A trainee's unsubmitted program for one exercise: saved while typing, brought back on the next visit."""

    __tablename__ = "drafts"
    __table_args__ = (UniqueConstraint("user_id", "exercise_id", name="uq_drafts_user_exercise"),)

    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    user_id: Mapped[int] = mapped_column(ForeignKey("users.id", ondelete="CASCADE"), index=True)
    exercise_id: Mapped[int] = mapped_column(ForeignKey("exercises.id", ondelete="CASCADE"), index=True)
    program: Mapped[str] = mapped_column(Text)
    updated_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)


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
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True), default=now)
