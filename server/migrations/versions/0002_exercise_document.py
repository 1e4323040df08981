"""Exercises keep their whole document in the format of core.exercises, which the grader reads.

Revision ID: 0002
Revises: 0001
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0002"
down_revision: str | None = "0001"
branch_labels: str | None = None
depends_on: str | None = None


def upgrade() -> None:
    """Add exercises.document."""
    with op.batch_alter_table("exercises", schema=None) as batch_op:
        batch_op.add_column(sa.Column("document", sa.JSON(), nullable=True))


def downgrade() -> None:
    """Drop exercises.document."""
    with op.batch_alter_table("exercises", schema=None) as batch_op:
        batch_op.drop_column("document")
