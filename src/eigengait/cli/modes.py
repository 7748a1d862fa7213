"""`eigengait modes`: a character's natural vibration modes as a table, JSON or a saved ModeSet."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.table import Table

from eigengait import json_text
from eigengait.cli.character import (
    BODY_OPTION,
    PARTNER_OPTION,
    RELAX_OPTION,
    STIFFNESS_OPTION,
    print_notes,
)
from eigengait.outputs import refuse_existing, require_suffix

console = Console()


def modes_command(
    character: str = typer.Argument(..., help="Built-in name, MJCF path or character sidecar."),
    phase: str = typer.Option("air", "--phase", help="air (free body) or ground (toe pinned)."),
    foot: Optional[str] = typer.Option(None, "--foot", help="Stance foot for the ground phase."),
    partners: Optional[list[str]] = PARTNER_OPTION,
    relax: Optional[str] = RELAX_OPTION,
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    save: Optional[Path] = typer.Option(None, "--save", help="Save the ModeSet (.npz)."),
    body: Optional[str] = BODY_OPTION,
    stiffness: Optional[str] = STIFFNESS_OPTION,
    force: bool = typer.Option(False, "--force", help="Overwrite an existing --save file."),
):
    """Natural vibration modes about the relax pose. Mode 1 is the lowest non-rigid mode."""
    from eigengait.character import load_character
    from eigengait.character.relax import parse_relax_argument
    from eigengait.modal import compute_modes

    require_suffix(save, (".npz",), "--save")
    refuse_existing([save], force)
    loaded = load_character(character, body, stiffness)
    print_notes(loaded)
    modes = compute_modes(loaded, phase, foot, parse_relax_argument(relax), partners or ())
    if save:
        modes.save(save)
    if as_json:
        print(json_text.dumps(modes.summary()))
        return
    title = f"{modes.character} — {modes.phase} phase" + (
        f", {modes.pinned_text()}" if modes.foot else ""
    )
    table = Table(
        title=title,
        caption=f"{modes.dofs} internal DOF; {modes.rigid_modes} rigid-body modes dropped",
    )
    table.add_column("mode", justify="right")
    table.add_column("frequency (Hz)", justify="right")
    table.add_column("period (s)", justify="right")
    table.add_column("largest joint motion")
    for i, f in enumerate(modes.frequencies_hz):
        col = modes.torque_basis[:, i]
        table.add_row(
            str(i + 1), f"{f:.3f}", f"{1 / f:.3f}", modes.dof_labels[int(abs(col).argmax())]
        )
    console.print(table)


def register(app: typer.Typer) -> None:
    """Add the `modes` command."""
    app.command("modes")(modes_command)
