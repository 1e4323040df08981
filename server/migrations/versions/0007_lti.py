"""LTI 1.3: registered platforms and their deployments, our signing keys, users/contexts/resource links from
launches, login states, used nonces and launches (server/lti/).

Revision ID: 0007_lti
Revises: 0006
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0007_lti"
down_revision: str | None = "0006"
branch_labels: str | None = None
depends_on: str | None = None

_TZ = sa.DateTime(timezone=True)


def _platform_fk() -> sa.ForeignKeyConstraint:
    return sa.ForeignKeyConstraint(["platform_id"], ["lti_platforms.id"], ondelete="CASCADE")


def upgrade() -> None:
    op.create_table(
        "lti_platforms",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("issuer", sa.String(500), nullable=False),
        sa.Column("client_id", sa.String(255), nullable=False),
        sa.Column("auth_login_url", sa.String(1000), nullable=False),
        sa.Column("token_url", sa.String(1000), nullable=False),
        sa.Column("jwks_url", sa.String(1000), nullable=False),
        sa.Column("name", sa.String(200), nullable=False),
        sa.Column("created_at", _TZ, nullable=False),
        sa.PrimaryKeyConstraint("id"),
        sa.UniqueConstraint("issuer", "client_id", name="uq_lti_platforms_issuer_client"),
    )
    op.create_index("ix_lti_platforms_issuer", "lti_platforms", ["issuer"])
    op.create_table(
        "lti_deployments",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("platform_id", sa.Integer(), nullable=False),
        sa.Column("deployment_id", sa.String(255), nullable=False),
        _platform_fk(),
        sa.PrimaryKeyConstraint("id"),
        sa.UniqueConstraint("platform_id", "deployment_id", name="uq_lti_deployments_platform_dep"),
    )
    op.create_index("ix_lti_deployments_platform_id", "lti_deployments", ["platform_id"])
    op.create_table(
        "lti_tool_keys",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("kid", sa.String(64), nullable=False),
        sa.Column("private_pem_encrypted", sa.Text(), nullable=False),
        sa.Column("public_jwk", sa.JSON(), nullable=False),
        sa.Column("created_at", _TZ, nullable=False),
        sa.Column("retired_at", _TZ, nullable=True),
        sa.PrimaryKeyConstraint("id"),
    )
    op.create_index("ix_lti_tool_keys_kid", "lti_tool_keys", ["kid"], unique=True)
    op.create_table(
        "lti_users",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("platform_id", sa.Integer(), nullable=False),
        sa.Column("sub", sa.String(255), nullable=False),
        sa.Column("user_id", sa.Integer(), nullable=False),
        sa.Column("name", sa.String(200), nullable=False),
        sa.Column("email", sa.String(320), nullable=False),
        _platform_fk(),
        sa.ForeignKeyConstraint(["user_id"], ["users.id"], ondelete="CASCADE"),
        sa.PrimaryKeyConstraint("id"),
        sa.UniqueConstraint("platform_id", "sub", name="uq_lti_users_platform_sub"),
    )
    op.create_index("ix_lti_users_platform_id", "lti_users", ["platform_id"])
    op.create_index("ix_lti_users_user_id", "lti_users", ["user_id"])
    op.create_table(
        "lti_contexts",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("platform_id", sa.Integer(), nullable=False),
        sa.Column("context_id", sa.String(255), nullable=False),
        sa.Column("course_id", sa.Integer(), nullable=True),
        sa.Column("title", sa.String(500), nullable=False),
        sa.Column("memberships_url", sa.String(1000), nullable=True),
        _platform_fk(),
        sa.ForeignKeyConstraint(["course_id"], ["courses.id"], ondelete="SET NULL"),
        sa.PrimaryKeyConstraint("id"),
        sa.UniqueConstraint("platform_id", "context_id", name="uq_lti_contexts_platform_context"),
    )
    op.create_index("ix_lti_contexts_platform_id", "lti_contexts", ["platform_id"])
    op.create_index("ix_lti_contexts_course_id", "lti_contexts", ["course_id"])
    op.create_table(
        "lti_resource_links",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("platform_id", sa.Integer(), nullable=False),
        sa.Column("context_pk", sa.Integer(), nullable=True),
        sa.Column("resource_link_id", sa.String(255), nullable=False),
        sa.Column("title", sa.String(500), nullable=False),
        sa.Column("exercise_slug", sa.String(80), nullable=True),
        sa.Column("assignment_id", sa.Integer(), nullable=True),
        sa.Column("lineitem_url", sa.String(1000), nullable=True),
        sa.Column("lineitems_url", sa.String(1000), nullable=True),
        sa.Column("ags_scopes", sa.JSON(), nullable=False),
        _platform_fk(),
        sa.ForeignKeyConstraint(["context_pk"], ["lti_contexts.id"], ondelete="SET NULL"),
        sa.ForeignKeyConstraint(["assignment_id"], ["assignments.id"], ondelete="SET NULL"),
        sa.PrimaryKeyConstraint("id"),
        sa.UniqueConstraint("platform_id", "resource_link_id", name="uq_lti_links_platform_link"),
    )
    op.create_index("ix_lti_resource_links_platform_id", "lti_resource_links", ["platform_id"])
    op.create_index("ix_lti_resource_links_context_pk", "lti_resource_links", ["context_pk"])
    op.create_table(
        "lti_login_states",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("state", sa.String(128), nullable=False),
        sa.Column("nonce", sa.String(128), nullable=False),
        sa.Column("platform_id", sa.Integer(), nullable=False),
        sa.Column("expires_at", _TZ, nullable=False),
        _platform_fk(),
        sa.PrimaryKeyConstraint("id"),
    )
    op.create_index("ix_lti_login_states_state", "lti_login_states", ["state"], unique=True)
    op.create_index("ix_lti_login_states_expires_at", "lti_login_states", ["expires_at"])
    op.create_table(
        "lti_nonces",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("platform_id", sa.Integer(), nullable=False),
        sa.Column("nonce", sa.String(255), nullable=False),
        sa.Column("expires_at", _TZ, nullable=False),
        _platform_fk(),
        sa.PrimaryKeyConstraint("id"),
        sa.UniqueConstraint("platform_id", "nonce", name="uq_lti_nonces_platform_nonce"),
    )
    op.create_index("ix_lti_nonces_expires_at", "lti_nonces", ["expires_at"])
    op.create_table(
        "lti_launches",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("platform_id", sa.Integer(), nullable=False),
        sa.Column("deployment_id", sa.String(255), nullable=False),
        sa.Column("message_type", sa.String(64), nullable=False),
        sa.Column("user_id", sa.Integer(), nullable=False),
        sa.Column("lti_user_pk", sa.Integer(), nullable=False),
        sa.Column("resource_link_pk", sa.Integer(), nullable=True),
        sa.Column("exercise_slug", sa.String(80), nullable=True),
        sa.Column("role", sa.String(20), nullable=False),
        sa.Column("ticket_hash", sa.String(64), nullable=False),
        sa.Column("ticket_expires_at", _TZ, nullable=False),
        sa.Column("ticket_used_at", _TZ, nullable=True),
        sa.Column("deep_link_return_url", sa.String(1000), nullable=True),
        sa.Column("deep_link_data", sa.Text(), nullable=True),
        sa.Column("created_at", _TZ, nullable=False),
        _platform_fk(),
        sa.ForeignKeyConstraint(["user_id"], ["users.id"], ondelete="CASCADE"),
        sa.ForeignKeyConstraint(["lti_user_pk"], ["lti_users.id"], ondelete="CASCADE"),
        sa.ForeignKeyConstraint(["resource_link_pk"], ["lti_resource_links.id"], ondelete="SET NULL"),
        sa.PrimaryKeyConstraint("id"),
    )
    op.create_index("ix_lti_launches_platform_id", "lti_launches", ["platform_id"])
    op.create_index("ix_lti_launches_user_id", "lti_launches", ["user_id"])
    op.create_index("ix_lti_launches_resource_link_pk", "lti_launches", ["resource_link_pk"])
    op.create_index("ix_lti_launches_ticket_hash", "lti_launches", ["ticket_hash"], unique=True)
    op.create_index("ix_lti_launches_created_at", "lti_launches", ["created_at"])


def downgrade() -> None:
    for table in (
        "lti_launches",
        "lti_nonces",
        "lti_login_states",
        "lti_resource_links",
        "lti_contexts",
        "lti_users",
        "lti_tool_keys",
        "lti_deployments",
        "lti_platforms",
    ):
        op.drop_table(table)
