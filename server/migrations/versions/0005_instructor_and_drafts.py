"""Students get the instructor who manages them; trainees' drafts are kept per user and exercise.

Revision ID: 0005
Revises: 0004
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0005"
down_revision: str | None = "0004"
branch_labels: str | None = None
depends_on: str | None = None


def upgrade() -> None:
    """Add users.instructor_id (null: nobody manages the user) and the table drafts."""
    with op.batch_alter_table("users", schema=None) as batch_op:
        batch_op.add_column(sa.Column("instructor_id", sa.Integer(), nullable=True))
        batch_op.create_index("ix_users_instructor_id", ["instructor_id"], unique=False)
        batch_op.create_foreign_key(
            "fk_users_instructor_id_users", "users", ["instructor_id"], ["id"], ondelete="SET NULL"
        )
    op.create_table(
        "drafts",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("user_id", sa.Integer(), nullable=False),
        sa.Column("exercise_id", sa.Integer(), nullable=False),
        sa.Column("program", sa.Text(), nullable=False),
        sa.Column("updated_at", sa.DateTime(timezone=True), nullable=False),
        sa.ForeignKeyConstraint(["exercise_id"], ["exercises.id"], ondelete="CASCADE"),
        sa.ForeignKeyConstraint(["user_id"], ["users.id"], ondelete="CASCADE"),
        sa.PrimaryKeyConstraint("id"),
        sa.UniqueConstraint("user_id", "exercise_id", name="uq_drafts_user_exercise"),
    )
    with op.batch_alter_table("drafts", schema=None) as batch_op:
        batch_op.create_index("ix_drafts_user_id", ["user_id"], unique=False)
        batch_op.create_index("ix_drafts_exercise_id", ["exercise_id"], unique=False)


def downgrade() -> None:
    """Drop the table drafts and users.instructor_id."""
    with op.batch_alter_table("drafts", schema=None) as batch_op:
        batch_op.drop_index("ix_drafts_exercise_id")
        batch_op.drop_index("ix_drafts_user_id")
    op.drop_table("drafts")
    with op.batch_alter_table("users", schema=None) as batch_op:
        batch_op.drop_constraint("fk_users_instructor_id_users", type_="foreignkey")
        batch_op.drop_index("ix_users_instructor_id")
        batch_op.drop_column("instructor_id")
