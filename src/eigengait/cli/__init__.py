"""The `eigengait` command: one sub-command per job.

Bad input raises `UserInputError`; `main()` prints it as one message on stderr, in the command line's words
(`flags.for_command_line`: the library's parameter names become flags), and exits with status 2.
Command groups living beside their package register themselves through a `register(app)` function.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.table import Table

from eigengait.cli.flags import for_command_line
from eigengait.cli.character import BODY_HELP, STIFFNESS_HELP, print_notes
from eigengait import json_text
from eigengait.errors import UserInputError
from eigengait.outputs import keep_mujoco_log_out_of_the_folder, refuse_existing, require_suffix, write_atomically

app = typer.Typer(
    add_completion=False, no_args_is_help=True, help="Physics-based character animation from natural vibration modes."
)
character_app = typer.Typer(no_args_is_help=True, help="Inspect and export characters.")
app.add_typer(character_app, name="character")
console = Console()


@app.command("characters")
def characters_command(as_json: bool = typer.Option(False, "--json", help="Print JSON instead of a table.")):
    """List the built-in characters with bodies, internal DOF and mass."""
    from eigengait.character import builtin_names, load_character
    from eigengait.sim import build_world

    rows = []
    for name in builtin_names():
        character = load_character(name)
        world = build_world(character)
        rows.append(
            {
                "name": name,
                "bodies": world.model.nbody - 1,
                "joints": len(character.joints),
                "dofs": character.internal_dofs,
                "mass_kg": round(world.mass(), 2),
                "feet": list(character.feet),
            }
        )
    if as_json:
        print(json_text.dumps(rows))
        return
    table = Table(title="Built-in characters")
    for col in ("name", "bodies", "joints", "internal DOF", "mass (kg)", "feet"):
        table.add_column(col)
    for r in rows:
        table.add_row(
            r["name"],
            str(r["bodies"]),
            str(r["joints"]),
            str(r["dofs"]),
            f"{r['mass_kg']:.1f}",
            ", ".join(r["feet"]) or "-",
        )
    console.print(table)


@character_app.command("export")
def character_export(
    name: str = typer.Argument(..., help="Built-in name, MJCF path or character sidecar."),
    output: Path = typer.Option(..., "-o", "--output", help="MJCF file to write."),
    relax: Optional[str] = typer.Option(None, "--relax", help="Relax pose: preset or JOINT=rx,ry,rz;..."),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing file."),
    body: Optional[str] = typer.Option(None, "--body", help=BODY_HELP),
    stiffness: Optional[str] = typer.Option(None, "--stiffness", help=STIFFNESS_HELP),
):
    """Write the character's MJCF exactly as simulated (springs, motors, contact spheres, floor)."""
    from eigengait.character import load_character
    from eigengait.character.relax import parse_relax_argument
    from eigengait.sim.world import build_world

    refuse_existing([output], force)
    world = build_world(load_character(name, body, stiffness), parse_relax_argument(relax))
    write_atomically(output, world.mjcf())
    console.print(f"wrote {output}")


@app.command("modes")
def modes_command(
    character: str = typer.Argument(..., help="Built-in name, MJCF path or character sidecar."),
    phase: str = typer.Option("air", "--phase", help="air (free body) or ground (toe pinned)."),
    foot: Optional[str] = typer.Option(None, "--foot", help="Stance foot for the ground phase."),
    relax: Optional[str] = typer.Option(None, "--relax", help="Relax pose: preset or JOINT=rx,ry,rz;..."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    save: Optional[Path] = typer.Option(None, "--save", help="Save the ModeSet (.npz)."),
    body: Optional[str] = typer.Option(None, "--body", help=BODY_HELP),
    stiffness: Optional[str] = typer.Option(None, "--stiffness", help=STIFFNESS_HELP),
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
    modes = compute_modes(loaded, phase, foot, parse_relax_argument(relax))
    if save:
        modes.save(save)
    if as_json:
        print(json_text.dumps(modes.summary()))
        return
    title = f"{modes.character} — {modes.phase} phase" + (f", {modes.foot} toe pinned" if modes.foot else "")
    table = Table(title=title, caption=f"{modes.dofs} internal DOF; {modes.rigid_modes} rigid-body modes dropped")
    table.add_column("mode", justify="right")
    table.add_column("frequency (Hz)", justify="right")
    table.add_column("period (s)", justify="right")
    table.add_column("largest joint motion")
    for i, f in enumerate(modes.frequencies_hz):
        col = modes.torque_basis[:, i]
        table.add_row(str(i + 1), f"{f:.3f}", f"{1 / f:.3f}", modes.dof_labels[int(abs(col).argmax())])
    console.print(table)


def _register_command_groups() -> None:
    from eigengait.cli.animate import register as register_animate
    from eigengait.cli.balance import register as register_balance
    from eigengait.cli.character import register as register_character
    from eigengait.cli.gait import register as register_gait
    from eigengait.cli.studio import register as register_studio
    from eigengait.cli.track import register as register_track

    from eigengait.cli.cloth import app as cloth_app

    app.add_typer(cloth_app, name="cloth", help="The FLEX3D deformable-surface simulator.")
    register_animate(app)
    register_character(app, character_app)
    register_gait(app)
    register_track(app)
    register_balance(app)
    register_studio(app)


_register_command_groups()


def _is_usage_error(exc: Exception) -> bool:
    """A command-line usage error from click or from the copy of click that typer carries (a bad option value)."""
    import click

    carried = tuple(k for k in typer.BadParameter.__mro__ if k.__name__ == "ClickException")
    return isinstance(exc, (click.ClickException, *carried))


def main() -> None:
    """Entry point: run the app, turning bad input into one message and exit status 2."""
    keep_mujoco_log_out_of_the_folder()
    if sys.argv[1:3] == ["sketch", "new"]:  # `sketch new MODEL`: the starter-sketch command
        sys.argv[1:3] = ["sketch-new"]
    try:
        code = app(standalone_mode=False)  # a typer.Exit inside a command comes back as the return value
    except UserInputError as err:
        Console(stderr=True).print(f"[bold red]error:[/] {for_command_line(err)}", highlight=False, soft_wrap=True)
        sys.exit(2)
    except (typer.Exit, SystemExit) as exc:
        code = getattr(exc, "exit_code", getattr(exc, "code", 0))
        sys.exit(code or 0)
    except typer.Abort:
        sys.exit(130)
    except Exception as exc:
        if _is_usage_error(exc):
            exc.show()
            sys.exit(2)
        raise
    sys.exit(code if isinstance(code, int) and not isinstance(code, bool) else 0)
