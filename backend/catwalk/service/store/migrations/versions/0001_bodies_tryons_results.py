"""The first tables: bodies, try-ons, results.

Revision ID: 0001
Revises:
Create Date: 2026-11-25
"""

import sqlalchemy as sa
from alembic import op

revision = "0001"
down_revision = None
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "bodies",
        sa.Column("id", sa.String(43), primary_key=True),
        sa.Column("created_at", sa.DateTime, nullable=False),
        sa.Column("source", sa.String(16), nullable=False),
        sa.Column("fit", sa.String(16), nullable=False),
        sa.Column("content_key", sa.String(64), nullable=False),
        sa.Column("sex", sa.String(8), nullable=False),
        sa.Column("measurements", sa.JSON, nullable=False),
        sa.Column("model_measurements", sa.JSON, nullable=False),
        sa.Column("scan_format", sa.String(8), nullable=True),
    )
    op.create_table(
        "tryons",
        sa.Column("id", sa.String(43), primary_key=True),
        sa.Column("key", sa.String(64), nullable=False),
        sa.Column("body_id", sa.String(43), sa.ForeignKey("bodies.id", ondelete="CASCADE"),
                  nullable=False),
        sa.Column("garment_id", sa.String(128), nullable=False),
        sa.Column("garment_version", sa.String(64), nullable=False),
        sa.Column("size", sa.String(32), nullable=False),
        sa.Column("fabric", sa.String(64), nullable=True),
        sa.Column("seconds", sa.Float, nullable=False),
        sa.Column("preset", sa.String(16), nullable=False),
        sa.Column("status", sa.String(16), nullable=False),
        sa.Column("progress", sa.Float, nullable=False),
        sa.Column("stage", sa.String(32), nullable=False),
        sa.Column("error", sa.Text, nullable=True),
        sa.Column("cached", sa.Boolean, nullable=False),
        sa.Column("cancel_requested", sa.Boolean, nullable=False),
        sa.Column("attempts", sa.Integer, nullable=False),
        sa.Column("worker", sa.String(255), nullable=True),
        sa.Column("created_at", sa.DateTime, nullable=False),
        sa.Column("enqueued_at", sa.DateTime, nullable=False),
        sa.Column("started_at", sa.DateTime, nullable=True),
        sa.Column("heartbeat_at", sa.DateTime, nullable=True),
        sa.Column("finished_at", sa.DateTime, nullable=True),
    )
    op.create_index("ix_tryons_status", "tryons", ["status"])
    op.create_index("ix_tryons_key", "tryons", ["key"])
    op.create_index("ix_tryons_body", "tryons", ["body_id"])
    op.create_table(
        "results",
        sa.Column("key", sa.String(64), primary_key=True),
        sa.Column("created_at", sa.DateTime, nullable=False),
        sa.Column("metrics", sa.JSON, nullable=False),
        sa.Column("glb_bytes", sa.Integer, nullable=False),
        sa.Column("web_bytes", sa.Integer, nullable=False),
        sa.Column("glb_sha256", sa.String(64), nullable=False),
        sa.Column("web_sha256", sa.String(64), nullable=False),
    )


def downgrade() -> None:
    op.drop_table("results")
    op.drop_index("ix_tryons_body", "tryons")
    op.drop_index("ix_tryons_key", "tryons")
    op.drop_index("ix_tryons_status", "tryons")
    op.drop_table("tryons")
    op.drop_table("bodies")
