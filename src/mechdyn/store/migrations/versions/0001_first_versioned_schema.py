"""The first versioned schema: a database written before mechdyn kept a schema version.

Tables such a database lacks are created. Its studies may keep each variant's values as
name → value objects (mechdyn before study columns): the names go to the study's ``columns``
and the variants' values become lists in that order, as the schema has them since.

Revision ID: 0001
Revises:
"""

import json

import sqlalchemy as sa
from alembic import op

revision = "0001"
down_revision = None
branch_labels = None
depends_on = None


def _json(v):
    return json.loads(v) if isinstance(v, str) else v


def upgrade() -> None:
    bind = op.get_bind()
    have = set(sa.inspect(bind).get_table_names())
    tz = sa.DateTime(timezone=True)
    if "mechdyn_runs" not in have:
        op.create_table(
            "mechdyn_runs",
            sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
            sa.Column("created_at", tz, nullable=False),
            sa.Column("analysis", sa.String(64), nullable=False, index=True),
            sa.Column("model_name", sa.String(256), nullable=False),
            sa.Column("model_path", sa.Text, nullable=False),
            sa.Column("model_sha256", sa.String(64), nullable=False, index=True),
            sa.Column("model_text", sa.Text, nullable=False),
            sa.Column("parameters", sa.JSON, nullable=False),
            sa.Column("scalars", sa.JSON, nullable=False),
            sa.Column("package_version", sa.String(64), nullable=False),
        )
    if "mechdyn_arrays" not in have:
        op.create_table(
            "mechdyn_arrays",
            sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
            sa.Column(
                "run_id",
                sa.Integer,
                sa.ForeignKey("mechdyn_runs.id", ondelete="CASCADE"),
                nullable=False,
                index=True,
            ),
            sa.Column("name", sa.String(256), nullable=False),
            sa.Column("unit", sa.String(64), nullable=False),
            sa.Column("data", sa.LargeBinary, nullable=False),
        )
    if "mechdyn_records" not in have:
        op.create_table(
            "mechdyn_records",
            sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
            sa.Column("created_at", tz, nullable=False),
            sa.Column("kind", sa.String(64), nullable=False, index=True),
            sa.Column("name", sa.String(256), nullable=False, index=True),
            sa.Column("data", sa.JSON, nullable=False),
            sa.Column("provenance", sa.Text, nullable=False),
            sa.Column("package_version", sa.String(64), nullable=False),
        )
    if "mechdyn_studies" not in have:
        op.create_table(
            "mechdyn_studies",
            sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
            sa.Column("name", sa.String(256), nullable=False, unique=True),
            sa.Column("kind", sa.String(32), nullable=False),
            sa.Column("analysis", sa.String(64), nullable=False),
            sa.Column("definition", sa.JSON, nullable=False),
            sa.Column("definition_sha256", sa.String(64), nullable=False),
            sa.Column("model_path", sa.Text, nullable=False),
            sa.Column("model_sha256", sa.String(64), nullable=False),
            sa.Column("model_files", sa.JSON, nullable=False),
            sa.Column("columns", sa.JSON, nullable=False),
            sa.Column("package_version", sa.String(64), nullable=False),
            sa.Column("created_at", tz, nullable=False),
        )
    elif "columns" not in {c["name"] for c in sa.inspect(bind).get_columns("mechdyn_studies")}:
        _studies_get_columns(bind)
    if "mechdyn_variants" not in have:
        op.create_table(
            "mechdyn_variants",
            sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
            sa.Column(
                "study_id",
                sa.Integer,
                sa.ForeignKey("mechdyn_studies.id", ondelete="CASCADE"),
                nullable=False,
                index=True,
            ),
            sa.Column("key", sa.String(64), nullable=False),
            sa.Column("position", sa.Integer, nullable=False),
            sa.Column("parameters", sa.JSON, nullable=False),
            sa.Column("given", sa.JSON, nullable=False),
            sa.Column("outputs", sa.JSON, nullable=False),
            sa.Column("status", sa.String(16), nullable=False, index=True),
            sa.Column("error", sa.Text, nullable=True),
            sa.Column("objective", sa.Float, nullable=True),
            sa.Column("model_sha256", sa.String(64), nullable=False),
            sa.Column("package_version", sa.String(64), nullable=False),
            sa.Column("created_at", tz, nullable=False),
            sa.UniqueConstraint("study_id", "key", name="uq_mechdyn_variant_key"),
        )
    if "mechdyn_variant_curves" not in have:
        op.create_table(
            "mechdyn_variant_curves",
            sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
            sa.Column(
                "variant_id",
                sa.Integer,
                sa.ForeignKey("mechdyn_variants.id", ondelete="CASCADE"),
                nullable=False,
                index=True,
            ),
            sa.Column("name", sa.String(256), nullable=False),
            sa.Column("unit", sa.String(64), nullable=False),
            sa.Column("data", sa.LargeBinary, nullable=False),
            sa.UniqueConstraint("variant_id", "name", name="uq_mechdyn_curve_name"),
        )


def _studies_get_columns(bind) -> None:
    """Variants kept as name → value objects: names to the study, values to lists in that order."""
    with op.batch_alter_table("mechdyn_studies") as batch:
        batch.add_column(sa.Column("columns", sa.JSON, nullable=True))
    studies = sa.table("mechdyn_studies", sa.column("id", sa.Integer), sa.column("columns", sa.JSON))
    variants = sa.table(
        "mechdyn_variants",
        sa.column("id", sa.Integer),
        sa.column("study_id", sa.Integer),
        sa.column("parameters", sa.JSON),
        sa.column("given", sa.JSON),
        sa.column("outputs", sa.JSON),
    )
    for (study_id,) in bind.execute(sa.select(studies.c.id)).all():
        rows = bind.execute(
            sa.select(variants.c.id, variants.c.parameters, variants.c.given, variants.c.outputs)
            .where(variants.c.study_id == study_id)
            .order_by(variants.c.id)
        ).all()
        pn: list[str] = []
        on: list[str] = []
        for _, p, _g, o in rows:
            pn += [k for k in (_json(p) or {}) if k not in pn]
            on += [k for k in (_json(o) or {}) if k not in on]
        for vid, p, g, o in rows:
            p, g, o = _json(p) or {}, _json(g) or {}, _json(o) or {}
            bind.execute(
                variants.update()
                .where(variants.c.id == vid)
                .values(
                    parameters=[p.get(k) for k in pn],
                    given=[g.get(k) for k in pn],
                    outputs=[o.get(k) for k in on],
                )
            )
        bind.execute(
            studies.update().where(studies.c.id == study_id).values(columns={"parameters": pn, "outputs": on})
        )


def downgrade() -> None:
    raise NotImplementedError("a results database is not taken back to before schema versions")
