"""The `eigengait` command: one sub-command per job.

Each command module adds its commands through a `register(app)` function; `build_app()` calls them
all, so importing this package registers nothing. Bad input and simulation blow-ups raise an
`EigengaitError`; `main()` prints it as one message on stderr, in the command line's words
(`flags.for_command_line`: the library's parameter names become flags), and exits with status 2.
"""

from __future__ import annotations

import sys

import typer
from rich.console import Console

from eigengait.cli.flags import for_command_line
from eigengait.errors import EigengaitError
from eigengait.outputs import keep_mujoco_log_out_of_the_folder


def build_app() -> typer.Typer:
    """The `eigengait` app with every command, in the order `--help` lists them."""
    from eigengait.cli import animate, balance, character, cloth, gait, modes, studio, track

    app = typer.Typer(
        add_completion=False,
        no_args_is_help=True,
        help="Physics-based character animation from natural vibration modes.",
    )
    for module in (character, modes, animate, gait, track, balance, studio, cloth):
        module.register(app)
    return app


def _is_usage_error(exc: Exception) -> bool:
    """A command-line usage error from click or from the copy of click that typer carries (a bad
    option value)."""
    import click

    carried = tuple(k for k in typer.BadParameter.__mro__ if k.__name__ == "ClickException")
    return isinstance(exc, (click.ClickException, *carried))


def main() -> None:
    """Entry point: build and run the app, turning bad input or a blow-up into one message and exit
    status 2."""
    keep_mujoco_log_out_of_the_folder()
    if sys.argv[1:3] == ["sketch", "new"]:  # `sketch new MODEL`: the starter-sketch command
        sys.argv[1:3] = ["sketch-new"]
    try:
        # a typer.Exit inside a command comes back as the return value
        code = build_app()(standalone_mode=False)
    except EigengaitError as err:
        Console(stderr=True).print(
            f"[bold red]error:[/] {for_command_line(err)}", highlight=False, soft_wrap=True
        )
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
