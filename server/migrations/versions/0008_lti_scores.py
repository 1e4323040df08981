"""LTI 1.3 Assignment and Grade Services: the queue of scores on their way to the platforms' line items
(server/lti/ags.py): one row per submission, retried with backoff until the platform took it.

Revision ID: 0008_lti_scores
Revises: 0007_lti
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0008_lti_scores"
down_revision: str | None = "0007_lti"
branch_labels: str | None = None
depends_on: str | None = None

_TZ = sa.DateTime(timezone=True)


def upgrade() -> None:
    op.create_table(
        "lti_scores",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("submission_id", sa.Integer(), nullable=False),
        sa.Column("platform_id", sa.Integer(), nullable=False),
        sa.Column("resource_link_pk", sa.Integer(), nullable=True),
        sa.Column("course_id", sa.Integer(), nullable=True),
        sa.Column("user_id", sa.Integer(), nullable=True),
        sa.Column("exercise_slug", sa.String(80), nullable=False),
        sa.Column("lineitem_url", sa.String(1000), nullable=False),
        sa.Column("lti_sub", sa.String(255), nullable=False),
        sa.Column("score_given", sa.Float(), nullable=True),
        sa.Column("activity_progress", sa.String(20), nullable=False, server_default="Completed"),
        sa.Column("timestamp", _TZ, nullable=False),
        sa.Column("state", sa.String(12), nullable=False),
        sa.Column("attempts", sa.Integer(), nullable=False),
        sa.Column("next_attempt_at", _TZ, nullable=False),
        sa.Column("last_error", sa.String(500), nullable=True),
        sa.Column("sent_at", _TZ, nullable=True),
        sa.Column("created_at", _TZ, nullable=False),
        sa.ForeignKeyConstraint(["submission_id"], ["submissions.id"], ondelete="CASCADE"),
        sa.ForeignKeyConstraint(["platform_id"], ["lti_platforms.id"], ondelete="CASCADE"),
        sa.ForeignKeyConstraint(["resource_link_pk"], ["lti_resource_links.id"], ondelete="SET NULL"),
        sa.ForeignKeyConstraint(["course_id"], ["courses.id"], ondelete="SET NULL"),
        sa.ForeignKeyConstraint(["user_id"], ["users.id"], ondelete="SET NULL"),
        sa.PrimaryKeyConstraint("id"),
        sa.UniqueConstraint("submission_id", name="uq_lti_scores_submission"),
    )
    op.create_index("ix_lti_scores_platform_id", "lti_scores", ["platform_id"])
    op.create_index("ix_lti_scores_resource_link_pk", "lti_scores", ["resource_link_pk"])
    op.create_index("ix_lti_scores_course_id", "lti_scores", ["course_id"])
    op.create_index("ix_lti_scores_state", "lti_scores", ["state"])
    op.create_index("ix_lti_scores_next_attempt_at", "lti_scores", ["next_attempt_at"])


def downgrade() -> None:
    op.drop_table("lti_scores")
