"""The ``gases`` subcommand: the catalogue of real gases, shipped, placed or to download."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ._common import Options, OverwriteOption, load_options, note, print_table, say, write_summary


class GasesOptions(Options):
    """Options of ``collisionkit gases``.

    Examples
    --------
    >>> GasesOptions(summary="gases.json").summary.name
    'gases.json'
    """

    summary: Path | None = None


def _processes(counts: dict) -> str:
    order = ("elastic", "excitation", "ionization", "attachment")
    return ", ".join(f"{counts[kind]} {kind}" for kind in order if counts.get(kind)) or "-"


def gases(
    summary: Annotated[Path | None, typer.Option("--summary", help="Write the catalogue as JSON to this file.")] = None,
    overwrite: OverwriteOption = None,
):
    """The real gases --gas takes: shipped cross-section sets, and those to download from LXCat into the data folder."""
    options = load_options(GasesOptions, None, dict(summary=summary, overwrite=overwrite))
    from ..transport import MODEL_GASES, data_folder
    from ..transport.catalogue import catalogue_rows

    rows = catalogue_rows()
    print_table("gases (collisionkit swarm --gas NAME, or a mixture --gas 'Ar:0.9,N2:0.1')",
                ("name", "species", "database", "processes", "status", "reference"),
                [(row["name"], row["species"], row["database"], _processes(row["processes"]), row["status"],
                  row["cite"]) for row in rows])
    for row in rows:
        if row["status"] == "missing":
            say(f"{row['name']}: {row['where']}")
    note(f"data folder: {data_folder()} (set COLLISIONKIT_DATA to change it); any LXCat file saved there as "
         "NAME.txt is used by --gas NAME; model gases (--model): " + ", ".join(MODEL_GASES))
    write_summary(options.summary, {"gases": rows, "data_folder": str(data_folder()),
                                    "models": list(MODEL_GASES)}, "gases")


def register(app: typer.Typer) -> None:
    """Add the ``gases`` command to the ``collisionkit`` app."""
    app.command("gases")(gases)
