"""`eigengait characters`, `character export`, `character inspect` and `sketch new`: the built-in
characters and a user's MJCF model.

The options that choose a character (`--body`, `--stiffness`) and its relax pose (`--relax`) are
shared with the commands that load one.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Optional

import typer
import yaml
from rich.console import Console
from rich.table import Table

from eigengait import json_text
from eigengait.outputs import refuse_existing, write_atomically
from eigengait.errors import UserInputError
from eigengait.inputs import check_range

console = Console()
BODY_OPTION = typer.Option(
    None,
    "--body",
    help=(
        "Root body of the creature in a scene with several (default: the largest articulated tree)."
    ),
)
STIFFNESS_OPTION = typer.Option(
    None,
    "--stiffness",
    help=(
        "`auto`: give joints without stiffness k = m·g·r/θ_sag (10° sag under the weight they "
        "carry)."
    ),
)
RELAX_OPTION = typer.Option(None, "--relax", help="Relax pose: preset or JOINT=rx,ry,rz;...")
PARTNER_OPTION = typer.Option(
    None,
    "--partner",
    help="Ground phase: a foot on the floor with the stance foot, its toe pinned too (repeatable).",
)


def print_notes(character) -> None:
    """What loading the model changed or guessed, on stderr (stdout stays clean for --json)."""
    for note in character.scene.notes:
        Console(stderr=True).print(f"note: {note}", highlight=False, soft_wrap=True)


def characters_command(
    as_json: bool = typer.Option(False, "--json", help="Print JSON instead of a table."),
):
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


def export_command(
    name: str = typer.Argument(..., help="Built-in name, MJCF path or character sidecar."),
    output: Path = typer.Option(..., "-o", "--output", help="MJCF file to write."),
    relax: Optional[str] = RELAX_OPTION,
    force: bool = typer.Option(False, "--force", help="Overwrite an existing file."),
    body: Optional[str] = BODY_OPTION,
    stiffness: Optional[str] = STIFFNESS_OPTION,
):
    """Write the character's MJCF exactly as simulated (springs, motors, contact spheres, floor)."""
    from eigengait.character import load_character
    from eigengait.character.relax import parse_relax_argument
    from eigengait.sim.world import build_world

    refuse_existing([output], force)
    world = build_world(load_character(name, body, stiffness), parse_relax_argument(relax))
    write_atomically(output, world.mjcf())
    console.print(f"wrote {output}")


def inspect_command(
    model: str = typer.Argument(..., help="Built-in name, MJCF path or character sidecar."),
    body: Optional[str] = BODY_OPTION,
    stiffness: Optional[str] = STIFFNESS_OPTION,
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    output: Optional[Path] = typer.Option(
        None, "-o", "--output", help="Write an editable sidecar NAME.eigengait.yaml."
    ),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing sidecar."),
):
    """What eigengait found or guessed in a model: root, joints, stiffness, feet, mirror pairs."""
    from eigengait.character import load_character
    from eigengait.character.report import describe, sidecar_yaml

    refuse_existing([output], force)
    character = load_character(model, body=body, stiffness=stiffness)
    info = describe(character)
    if output is not None:
        write_atomically(output, sidecar_yaml(character, output))
    if as_json:
        print(json_text.dumps(info))
        return
    root = info["root"]
    console.print(
        f"[bold]{info['character']}[/] — {info['internal_dofs']} internal DOF; root "
        f"'{root['body']}' "
        f"({root['kind']}{': ' + ', '.join(root['joints']) if root['joints'] else ''})"
    )
    for note in info["notes"]:
        console.print(f"note: {note}")
    table = Table(title="joints")
    for col in ("joint", "kind", "stiffness (N·m/rad)", "source"):
        table.add_column(col)
    for j in info["joints"]:
        table.add_row(
            j["name"],
            j["kind"],
            ", ".join(f"{k:.3g}" for k in j["stiffness"]),
            j["stiffness_source"],
        )
    console.print(table)
    feet = (
        ", ".join(f"{n}{' (guessed)' if f['guessed'] else ''}" for n, f in info["feet"].items())
        or "(none)"
    )
    console.print(f"feet: {feet}")
    console.print(
        "mirror pairs: "
        + (", ".join(f"{a}↔{b}" for a, b in info["mirror_pairs"].items()) or "(none)")
    )
    if output is not None:
        console.print(f"wrote {output}")


def sketch_new_command(
    model: str = typer.Argument(..., help="Built-in name, MJCF path or character sidecar."),
    output: Path = typer.Option(..., "-o", "--output", help="Sketch file to write (.yaml)."),
    body: Optional[str] = BODY_OPTION,
    stiffness: Optional[str] = STIFFNESS_OPTION,
    random: Optional[int] = typer.Option(
        None,
        "--random",
        help="Draw the priority modes and signs from this seed (the thesis's random sketches).",
    ),
    procedure: int = typer.Option(
        1, "--procedure", help="With --random: 1 (3 air + 4 ground modes, ±0.4) or 2."
    ),
    force: bool = typer.Option(False, "--force", help="Overwrite existing files."),
):
    """Write a starter sketch (or with --random a random one, thesis §5.3.4); for a user's MJCF
    (or a sidecar with --body/--stiffness), also a character sidecar `NAME.eigengait.yaml` beside it
    that the sketch refers to."""
    from eigengait.character import builtin_names, load_character
    from eigengait.character.metadata import SIDECAR_SUFFIX
    from eigengait.character.report import sidecar_yaml
    from eigengait.control.random_sketch import PROCEDURES, random_sketch
    from eigengait.control.starter import starter_sketch

    if procedure not in PROCEDURES:
        raise UserInputError(
            f"unknown procedure {procedure}", field="--procedure", fix="use 1 or 2"
        )
    check_range(random, "--random", 0, 2**63 - 1)
    character = load_character(model, body=body, stiffness=stiffness)
    print_notes(character)
    builtin = model in builtin_names()
    standalone = character.reference != character.path and body is None and stiffness is None
    sidecar = None if builtin or standalone else output.with_name(character.name + SIDECAR_SUFFIX)
    refuse_existing([output, sidecar], force)
    target = character.reference if standalone else sidecar
    reference = model if builtin else os.path.relpath(target.resolve(), output.resolve().parent)
    sketch = (
        starter_sketch(character, reference)
        if random is None
        else random_sketch(character, reference, random, procedure)
    )
    if sidecar is not None:
        write_atomically(sidecar, sidecar_yaml(character, sidecar))
        console.print(f"wrote {sidecar}")
    write_atomically(output, yaml.safe_dump(sketch, sort_keys=False, allow_unicode=True))
    console.print(
        f"wrote {output}: feet {', '.join(sketch['feet'])}, period {sketch['timing']['period']} s"
    )


def register(app: typer.Typer) -> None:
    """Add `characters`, the `character` group (`export`, `inspect`) and the hidden `sketch-new`
    that `main` runs for `sketch new`."""
    app.command("characters")(characters_command)
    app.command("sketch-new", hidden=True)(sketch_new_command)
    character_app = typer.Typer(no_args_is_help=True, help="Inspect and export characters.")
    character_app.command("export")(export_command)
    character_app.command("inspect")(inspect_command)
    app.add_typer(character_app, name="character")
