"""Merchants, their garments and each garment's versions (with the dressing check per size).

Revision ID: 0003
Revises: 0002
Create Date: 2026-11-26
"""

import sqlalchemy as sa
from alembic import op

revision = "0003"
down_revision = "0002"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "merchants",
        sa.Column("id", sa.String(43), primary_key=True),
        sa.Column("name", sa.String(64), nullable=False, unique=True),
        sa.Column("key_sha256", sa.String(64), nullable=False, unique=True),
        sa.Column("created_at", sa.DateTime, nullable=False),
        sa.Column("revoked_at", sa.DateTime, nullable=True),
    )
    op.create_table(
        "merchant_garments",
        sa.Column("id", sa.String(64), primary_key=True),
        sa.Column("merchant_id", sa.String(43),
                  sa.ForeignKey("merchants.id", ondelete="CASCADE"), nullable=False),
        sa.Column("name", sa.String(200), nullable=False),
        sa.Column("type", sa.String(32), nullable=False),
        sa.Column("version", sa.Integer, nullable=False),
        sa.Column("published_version", sa.Integer, nullable=True),
        sa.Column("created_at", sa.DateTime, nullable=False),
        sa.Column("updated_at", sa.DateTime, nullable=False),
        sa.Column("deleted_at", sa.DateTime, nullable=True),
    )
    op.create_index("ix_merchant_garments_merchant", "merchant_garments", ["merchant_id"])
    op.create_table(
        "garment_versions",
        sa.Column("garment_id", sa.String(64),
                  sa.ForeignKey("merchant_garments.id", ondelete="CASCADE"), primary_key=True),
        sa.Column("version", sa.Integer, primary_key=True),
        sa.Column("content", sa.String(64), nullable=False),
        sa.Column("created_at", sa.DateTime, nullable=False),
        sa.Column("sizes", sa.JSON, nullable=False),
        sa.Column("warnings", sa.JSON, nullable=False),
        sa.Column("dressing", sa.JSON, nullable=False),
        sa.Column("check_status", sa.String(16), nullable=False),
        sa.Column("check_attempts", sa.Integer, nullable=False),
        sa.Column("check_beat_at", sa.DateTime, nullable=True),
    )


def downgrade() -> None:
    op.drop_table("garment_versions")
    op.drop_index("ix_merchant_garments_merchant", "merchant_garments")
    op.drop_table("merchant_garments")
    op.drop_table("merchants")
