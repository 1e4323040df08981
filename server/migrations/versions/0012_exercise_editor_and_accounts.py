"""Exercises written in the browser and accounts without the command line: an exercise's visibility (draft,
courses, public), version and archive mark, its earlier versions and an instructor's own drawing; the version a
submission was graded against; a user's must-change-password mark, deactivation and the course they signed up to.

Revision ID: 0012
Revises: 0011
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0012"
down_revision: str | None = "0011"
branch_labels: str | None = None
depends_on: str | None = None

_TZ = sa.DateTime(timezone=True)


def upgrade() -> None:
    with op.batch_alter_table("exercises", schema=None) as batch_op:
        # every exercise so far was public to every trainee the moment it was accepted
        batch_op.add_column(sa.Column("visibility", sa.String(20), nullable=False, server_default="public"))
        batch_op.add_column(sa.Column("version", sa.Integer(), nullable=False, server_default="1"))
        batch_op.add_column(sa.Column("archived_at", _TZ, nullable=True))
    op.create_table(
        "exercise_versions",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("exercise_id", sa.Integer(), nullable=False),
        sa.Column("version", sa.Integer(), nullable=False),
        sa.Column("title_de", sa.String(200), nullable=False),
        sa.Column("document", sa.JSON(), nullable=True),
        sa.Column("created_by", sa.Integer(), nullable=True),
        sa.Column("created_at", _TZ, nullable=False),
        sa.ForeignKeyConstraint(["exercise_id"], ["exercises.id"], ondelete="CASCADE"),
        sa.ForeignKeyConstraint(["created_by"], ["users.id"], ondelete="SET NULL"),
        sa.PrimaryKeyConstraint("id"),
        sa.UniqueConstraint("exercise_id", "version", name="uq_exercise_versions_exercise_version"),
    )
    op.create_index("ix_exercise_versions_exercise_id", "exercise_versions", ["exercise_id"])
    op.create_table(
        "exercise_drawings",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("exercise_id", sa.Integer(), nullable=False),
        sa.Column("media_type", sa.String(40), nullable=False),
        sa.Column("filename", sa.String(200), nullable=False),
        sa.Column("data", sa.LargeBinary(), nullable=False),
        sa.Column("created_at", _TZ, nullable=False),
        sa.ForeignKeyConstraint(["exercise_id"], ["exercises.id"], ondelete="CASCADE"),
        sa.PrimaryKeyConstraint("id"),
        sa.UniqueConstraint("exercise_id", name="uq_exercise_drawings_exercise"),
    )
    with op.batch_alter_table("submissions", schema=None) as batch_op:
        batch_op.add_column(sa.Column("exercise_version", sa.Integer(), nullable=True))
    with op.batch_alter_table("users", schema=None) as batch_op:
        batch_op.add_column(
            sa.Column("must_change_password", sa.Boolean(), nullable=False, server_default=sa.false())
        )
        batch_op.add_column(sa.Column("deactivated_at", _TZ, nullable=True))
        batch_op.add_column(sa.Column("signup_course_id", sa.Integer(), nullable=True))
        batch_op.create_foreign_key(
            "fk_users_signup_course_id_courses", "courses", ["signup_course_id"], ["id"], ondelete="SET NULL"
        )


def downgrade() -> None:
    with op.batch_alter_table("users", schema=None) as batch_op:
        batch_op.drop_constraint("fk_users_signup_course_id_courses", type_="foreignkey")
        batch_op.drop_column("signup_course_id")
        batch_op.drop_column("deactivated_at")
        batch_op.drop_column("must_change_password")
    with op.batch_alter_table("submissions", schema=None) as batch_op:
        batch_op.drop_column("exercise_version")
    op.drop_table("exercise_drawings")
    op.drop_index("ix_exercise_versions_exercise_id", table_name="exercise_versions")
    op.drop_table("exercise_versions")
    with op.batch_alter_table("exercises", schema=None) as batch_op:
        batch_op.drop_column("archived_at")
        batch_op.drop_column("version")
        batch_op.drop_column("visibility")
