"""Courses (classes) with members, assignments (practice and exams); submissions know their assignment.

The interim rule of 0005 (users.instructor_id: an instructor sees the students they manage) becomes a course:
every instructor with managed students gets a course "Meine Klasse" with them.

Revision ID: 0006
Revises: 0005
"""

from __future__ import annotations

import secrets
from datetime import UTC, datetime

import sqlalchemy as sa
from alembic import op

revision: str = "0006"
down_revision: str | None = "0005"
branch_labels: str | None = None
depends_on: str | None = None

_CODE_ALPHABET = "ABCDEFGHJKLMNPQRSTUVWXYZ23456789"


def upgrade() -> None:
    op.create_table(
        "courses",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("name", sa.String(200), nullable=False),
        sa.Column("join_code", sa.String(32), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.PrimaryKeyConstraint("id"),
    )
    op.create_index("ix_courses_join_code", "courses", ["join_code"], unique=True)
    op.create_table(
        "course_members",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("course_id", sa.Integer(), nullable=False),
        sa.Column("user_id", sa.Integer(), nullable=False),
        sa.Column("role", sa.String(20), nullable=False),
        sa.ForeignKeyConstraint(["course_id"], ["courses.id"], ondelete="CASCADE"),
        sa.ForeignKeyConstraint(["user_id"], ["users.id"], ondelete="CASCADE"),
        sa.PrimaryKeyConstraint("id"),
        sa.UniqueConstraint("course_id", "user_id", name="uq_course_members_course_user"),
    )
    op.create_index("ix_course_members_course_id", "course_members", ["course_id"])
    op.create_index("ix_course_members_user_id", "course_members", ["user_id"])
    op.create_table(
        "assignments",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("course_id", sa.Integer(), nullable=False),
        sa.Column("title", sa.String(200), nullable=False),
        sa.Column("exercises", sa.JSON(), nullable=False),
        sa.Column("mode", sa.String(20), nullable=False),
        sa.Column("late", sa.String(20), nullable=False),
        sa.Column("opens_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("deadline", sa.DateTime(timezone=True), nullable=False),
        sa.Column("duration_minutes", sa.Integer(), nullable=True),
        sa.Column("settings", sa.JSON(), nullable=False),
        sa.Column("released_at", sa.DateTime(timezone=True), nullable=True),
        sa.Column("finalized_at", sa.DateTime(timezone=True), nullable=True),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.ForeignKeyConstraint(["course_id"], ["courses.id"], ondelete="CASCADE"),
        sa.PrimaryKeyConstraint("id"),
    )
    op.create_index("ix_assignments_course_id", "assignments", ["course_id"])
    with op.batch_alter_table("submissions", schema=None) as batch_op:
        batch_op.add_column(sa.Column("assignment_id", sa.Integer(), nullable=True))
        batch_op.add_column(sa.Column("late", sa.Boolean(), nullable=False, server_default=sa.false()))
        batch_op.add_column(sa.Column("held", sa.Boolean(), nullable=False, server_default=sa.false()))
        batch_op.add_column(sa.Column("auto", sa.Boolean(), nullable=False, server_default=sa.false()))
        batch_op.create_index("ix_submissions_assignment_id", ["assignment_id"], unique=False)
        batch_op.create_foreign_key(
            "fk_submissions_assignment_id_assignments",
            "assignments",
            ["assignment_id"],
            ["id"],
            ondelete="SET NULL",
        )
    _courses_from_managed_students()


def _courses_from_managed_students() -> None:
    """Every instructor who manages students gets the course "Meine Klasse" with them."""
    conn = op.get_bind()
    users = sa.table("users", sa.column("id", sa.Integer), sa.column("instructor_id", sa.Integer))
    courses = sa.table(
        "courses",
        sa.column("id", sa.Integer),
        sa.column("name", sa.String),
        sa.column("join_code", sa.String),
        sa.column("created_at", sa.DateTime(timezone=True)),
    )
    members = sa.table(
        "course_members",
        sa.column("course_id", sa.Integer),
        sa.column("user_id", sa.Integer),
        sa.column("role", sa.String),
    )
    managed: dict[int, list[int]] = {}
    for uid, boss in conn.execute(
        sa.select(users.c.id, users.c.instructor_id).where(users.c.instructor_id.is_not(None))
    ).all():
        managed.setdefault(boss, []).append(uid)
    for boss, students in sorted(managed.items()):
        code = "".join(secrets.choice(_CODE_ALPHABET) for _ in range(8))
        course_id = conn.execute(
            courses.insert()
            .values(name="Meine Klasse", join_code=code, created_at=datetime.now(UTC))
            .returning(courses.c.id)
        ).scalar_one()
        conn.execute(
            members.insert(),
            [
                {"course_id": course_id, "user_id": boss, "role": "instructor"},
                *({"course_id": course_id, "user_id": s, "role": "student"} for s in students if s != boss),
            ],
        )


def downgrade() -> None:
    with op.batch_alter_table("submissions", schema=None) as batch_op:
        batch_op.drop_constraint("fk_submissions_assignment_id_assignments", type_="foreignkey")
        batch_op.drop_index("ix_submissions_assignment_id")
        batch_op.drop_column("auto")
        batch_op.drop_column("held")
        batch_op.drop_column("late")
        batch_op.drop_column("assignment_id")
    op.drop_index("ix_assignments_course_id", table_name="assignments")
    op.drop_table("assignments")
    op.drop_index("ix_course_members_user_id", table_name="course_members")
    op.drop_index("ix_course_members_course_id", table_name="course_members")
    op.drop_table("course_members")
    op.drop_index("ix_courses_join_code", table_name="courses")
    op.drop_table("courses")
