"""The `eigengait` app is built when it runs: importing the package registers no command, and every
build lists the commands `eigengait --help` has always listed."""

import subprocess
import sys

import typer

from eigengait.cli import build_app

COMMANDS = [
    "characters",
    "modes",
    "palette",
    "animate",
    "sketch",
    "optimize",
    "play",
    "harden",
    "gaits",
    "demo",
    "track",
    "balance",
    "studio",
    "character",
    "cloth",
]
GROUPS = {"character": ["export", "inspect"], "cloth": ["examples", "run", "modes"]}

IMPORT_ONLY = """
import sys, typer
import eigengait.cli as cli
print(sorted(m for m in sys.modules if m.startswith("eigengait.cli.")))
print(any(isinstance(v, typer.Typer) for v in vars(cli).values()))
"""


def _listed(group) -> list[str]:
    return [name for name in group.list_commands(None) if not group.commands[name].hidden]


def test_importing_the_cli_registers_no_command():
    done = subprocess.run(
        [sys.executable, "-c", IMPORT_ONLY], capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == ["['eigengait.cli.flags']", "False"]


def test_help_lists_the_same_commands_in_the_same_order():
    app = typer.main.get_command(build_app())
    assert _listed(app) == COMMANDS
    assert {name: _listed(app.commands[name]) for name in GROUPS} == GROUPS
    assert app.commands["sketch-new"].hidden


def test_each_build_is_a_new_app_with_each_command_once():
    first, second = build_app(), build_app()
    assert first is not second
    for app in (first, second):
        assert len(app.registered_commands) == len({c.name for c in app.registered_commands})
        assert [g.name for g in app.registered_groups] == list(GROUPS)
        assert [len(g.typer_instance.registered_commands) for g in app.registered_groups] == [2, 3]
