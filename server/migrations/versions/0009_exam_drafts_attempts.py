"""Exams a school can trust: an exam's drafts belong to that exam, a limited number of submissions is a constraint
of the database, and one replica at a time finalises an ended exam.

- drafts.assignment_id: null for the practice draft (one per user and exercise), else the exam the draft is for
  (one per user, exercise and exam); deleting the exam deletes its drafts.
- submissions.attempt: the number of a submission to an assignment with a limit (1 … max_submissions), unique per
  assignment, user and exercise — two submissions racing for the last attempt cannot both be stored.
- assignments.finalizing_until: the lease of the replica that submits an ended exam's drafts.

Revision ID: 0009
Revises: 0008_lti_scores
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0009"
down_revision: str | None = "0008_lti_scores"
branch_labels: str | None = None
depends_on: str | None = None

_PRACTICE = sa.text("assignment_id IS NULL")


def upgrade() -> None:
    with op.batch_alter_table("drafts", schema=None) as batch_op:
        batch_op.add_column(sa.Column("assignment_id", sa.Integer(), nullable=True))
        batch_op.drop_constraint("uq_drafts_user_exercise", type_="unique")
        batch_op.create_foreign_key(
            "fk_drafts_assignment_id_assignments",
            "assignments",
            ["assignment_id"],
            ["id"],
            ondelete="CASCADE",
        )
        batch_op.create_unique_constraint(
            "uq_drafts_user_exercise_assignment", ["user_id", "exercise_id", "assignment_id"]
        )
    op.create_index(
        "uq_drafts_practice",
        "drafts",
        ["user_id", "exercise_id"],
        unique=True,
        sqlite_where=_PRACTICE,
        postgresql_where=_PRACTICE,
    )
    with op.batch_alter_table("submissions", schema=None) as batch_op:
        batch_op.add_column(sa.Column("attempt", sa.Integer(), nullable=True))
        batch_op.create_unique_constraint(
            "uq_submissions_attempt", ["assignment_id", "user_id", "exercise_id", "attempt"]
        )
    with op.batch_alter_table("assignments", schema=None) as batch_op:
        batch_op.add_column(sa.Column("finalizing_until", sa.DateTime(timezone=True), nullable=True))


def downgrade() -> None:
    with op.batch_alter_table("assignments", schema=None) as batch_op:
        batch_op.drop_column("finalizing_until")
    with op.batch_alter_table("submissions", schema=None) as batch_op:
        batch_op.drop_constraint("uq_submissions_attempt", type_="unique")
        batch_op.drop_column("attempt")
    op.drop_index("uq_drafts_practice", table_name="drafts")
    op.execute(
        "DELETE FROM drafts WHERE assignment_id IS NOT NULL"
    )  # exam drafts have no place in the old table
    with op.batch_alter_table("drafts", schema=None) as batch_op:
        batch_op.drop_constraint("uq_drafts_user_exercise_assignment", type_="unique")
        batch_op.drop_constraint("fk_drafts_assignment_id_assignments", type_="foreignkey")
        batch_op.drop_column("assignment_id")
        batch_op.create_unique_constraint("uq_drafts_user_exercise", ["user_id", "exercise_id"])
