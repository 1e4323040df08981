"""LTI dynamic registration URLs are single use: the codes used so far (server/lti/registration.py), each kept
until it would have expired anyway.

Revision ID: 0010
Revises: 0009
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0010"
down_revision: str | None = "0009"
branch_labels: str | None = None
depends_on: str | None = None

_TZ = sa.DateTime(timezone=True)


def upgrade() -> None:
    op.create_table(
        "lti_registration_codes",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("jti", sa.String(64), nullable=False),
        sa.Column("used_at", _TZ, nullable=False),
        sa.Column("expires_at", _TZ, nullable=False),
        sa.PrimaryKeyConstraint("id"),
        sa.UniqueConstraint("jti", name="uq_lti_registration_codes_jti"),
    )
    op.create_index("ix_lti_registration_codes_expires_at", "lti_registration_codes", ["expires_at"])


def downgrade() -> None:
    op.drop_table("lti_registration_codes")
