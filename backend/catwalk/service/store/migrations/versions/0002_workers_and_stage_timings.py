"""Workers seen (for the metrics), each try-on's seconds per stage, and at most one active
try-on per body and content key (a unique partial index: two requests at once get one job).

Revision ID: 0002
Revises: 0001
Create Date: 2026-11-25
"""

import sqlalchemy as sa
from alembic import op

revision = "0002"
down_revision = "0001"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "workers",
        sa.Column("id", sa.String(255), primary_key=True),
        sa.Column("host", sa.String(255), nullable=False),
        sa.Column("pid", sa.Integer, nullable=False),
        sa.Column("concurrency", sa.Integer, nullable=False),
        sa.Column("started_at", sa.DateTime, nullable=False),
        sa.Column("seen_at", sa.DateTime, nullable=False),
    )
    with op.batch_alter_table("tryons") as batch:
        batch.add_column(sa.Column("timings", sa.JSON, nullable=True))
    op.create_index("ix_tryons_finished", "tryons", ["finished_at"])
    # before the index: a database of 0001 may hold two active rows for one body and key (two
    # requests at once were not yet kept apart); all but the first of each are cancelled
    op.execute("UPDATE tryons SET status = 'cancelled', stage = 'cancelled', "
               "finished_at = CURRENT_TIMESTAMP "
               "WHERE status IN ('queued', 'running') AND id NOT IN ("
               "SELECT MIN(id) FROM tryons WHERE status IN ('queued', 'running') "
               "GROUP BY body_id, key)")
    active = sa.text("status IN ('queued', 'running')")
    op.create_index("ux_tryons_active", "tryons", ["body_id", "key"], unique=True,
                    postgresql_where=active, sqlite_where=active)


def downgrade() -> None:
    op.drop_index("ux_tryons_active", "tryons")
    op.drop_index("ix_tryons_finished", "tryons")
    with op.batch_alter_table("tryons") as batch:
        batch.drop_column("timings")
    op.drop_table("workers")
