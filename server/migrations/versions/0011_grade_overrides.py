"""The teacher's last word: a score override with a comment on a submission (the current one on the submission,
every change kept in grade_overrides with who and when).

Revision ID: 0011
Revises: 0010
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0011"
down_revision: str | None = "0010"
branch_labels: str | None = None
depends_on: str | None = None

_TZ = sa.DateTime(timezone=True)


def upgrade() -> None:
    with op.batch_alter_table("submissions", schema=None) as batch_op:
        batch_op.add_column(sa.Column("override_score", sa.Integer(), nullable=True))
        batch_op.add_column(sa.Column("override_comment", sa.Text(), nullable=True))
        batch_op.add_column(sa.Column("override_by", sa.Integer(), nullable=True))
        batch_op.add_column(sa.Column("override_at", _TZ, nullable=True))
        batch_op.create_foreign_key(
            "fk_submissions_override_by_users", "users", ["override_by"], ["id"], ondelete="SET NULL"
        )
    op.create_table(
        "grade_overrides",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("submission_id", sa.Integer(), nullable=False),
        sa.Column("score", sa.Integer(), nullable=True),
        sa.Column("comment", sa.Text(), nullable=False),
        sa.Column("by_user_id", sa.Integer(), nullable=True),
        sa.Column("created_at", _TZ, nullable=False),
        sa.ForeignKeyConstraint(["submission_id"], ["submissions.id"], ondelete="CASCADE"),
        sa.ForeignKeyConstraint(["by_user_id"], ["users.id"], ondelete="SET NULL"),
        sa.PrimaryKeyConstraint("id"),
    )
    op.create_index("ix_grade_overrides_submission_id", "grade_overrides", ["submission_id"])


def downgrade() -> None:
    op.drop_index("ix_grade_overrides_submission_id", table_name="grade_overrides")
    op.drop_table("grade_overrides")
    with op.batch_alter_table("submissions", schema=None) as batch_op:
        batch_op.drop_constraint("fk_submissions_override_by_users", type_="foreignkey")
        batch_op.drop_column("override_at")
        batch_op.drop_column("override_by")
        batch_op.drop_column("override_comment")
        batch_op.drop_column("override_score")
