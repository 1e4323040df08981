"""Submissions remember the idempotency key they were made with, so that a repeated request finds them.

Revision ID: 0003
Revises: 0002
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0003"
down_revision: str | None = "0002"
branch_labels: str | None = None
depends_on: str | None = None


def upgrade() -> None:
    """Add submissions.idempotency_key (unique: "<who>:<key>")."""
    with op.batch_alter_table("submissions", schema=None) as batch_op:
        batch_op.add_column(sa.Column("idempotency_key", sa.String(300), nullable=True))
        batch_op.create_index("ix_submissions_idempotency_key", ["idempotency_key"], unique=True)


def downgrade() -> None:
    """Drop submissions.idempotency_key."""
    with op.batch_alter_table("submissions", schema=None) as batch_op:
        batch_op.drop_index("ix_submissions_idempotency_key")
        batch_op.drop_column("idempotency_key")
