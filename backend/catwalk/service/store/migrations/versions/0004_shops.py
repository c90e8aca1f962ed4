"""Shops: each merchant's publishable key (``pk_…``, for its shop's pages) and the origins its
pages may use it from; a body made on a shop names the merchant and (hashed) the shopper.

Revision ID: 0004
Revises: 0003
Create Date: 2026-11-27
"""

import secrets

import sqlalchemy as sa
from alembic import op

revision = "0004"
down_revision = "0003"
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table("merchants") as batch:
        batch.add_column(sa.Column("publishable_key", sa.String(64), nullable=True))
        batch.add_column(sa.Column("origins", sa.JSON, nullable=True))
    # every merchant made before has its publishable key too (no origin allowed yet)
    merchants = sa.table("merchants", sa.column("id", sa.String),
                         sa.column("publishable_key", sa.String))
    conn = op.get_bind()
    for (merchant_id,) in conn.execute(sa.select(merchants.c.id)).all():
        conn.execute(merchants.update().where(merchants.c.id == merchant_id)
                     .values(publishable_key="pk_" + secrets.token_urlsafe(24)))
    op.create_index("ux_merchants_publishable_key", "merchants", ["publishable_key"],
                    unique=True)
    with op.batch_alter_table("bodies") as batch:
        batch.add_column(sa.Column("merchant_id", sa.String(43), nullable=True))
        batch.add_column(sa.Column("shopper", sa.String(64), nullable=True))
    op.create_index("ix_bodies_shop", "bodies", ["merchant_id", "shopper"])


def downgrade() -> None:
    op.drop_index("ix_bodies_shop", "bodies")
    with op.batch_alter_table("bodies") as batch:
        batch.drop_column("shopper")
        batch.drop_column("merchant_id")
    op.drop_index("ux_merchants_publishable_key", "merchants")
    with op.batch_alter_table("merchants") as batch:
        batch.drop_column("origins")
        batch.drop_column("publishable_key")
