"""`mimic robots`: the robots mimic knows, with their joints, mass, actuators and world."""

from __future__ import annotations

import json
from typing import Annotated

import typer
from rich.table import Table

from mimic.cli.common import console, reports_errors
from mimic.errors import MimicError
from mimic.robot.registry import get_robot, robot_names


def _row(name: str) -> dict:
    """One robot as plain data; a robot that cannot be loaded says why."""
    try:
        robot = get_robot(name)
    except MimicError as err:  # a league robot without rcsssmj installed: list it anyway
        return {"name": name, "error": str(err)}
    return {
        "name": robot.name,
        "title": robot.title,
        "joints": robot.num_joints,
        "mass_kg": round(robot.mass_kg, 3),
        "actuator": robot.actuator.kind,
        "actuator_detail": robot.actuator.describe(),
        "world": robot.world,
        "mjcf_path": str(robot.mjcf_path) if robot.mjcf_path else None,
    }


@reports_errors
def robots(
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
) -> None:
    """List the robots: name, joints, mass, actuator model and the world they play in."""
    rows = [_row(name) for name in robot_names()]
    if as_json:
        console.print_json(json.dumps(rows))
        return
    table = Table(box=None, header_style="bold")
    for column, justify in (
        ("name", "left"),
        ("joints", "right"),
        ("mass kg", "right"),
        ("actuator model", "left"),
        ("world", "left"),
    ):
        table.add_column(column, justify=justify)
    for row in rows:
        if "error" in row:
            table.add_row(row["name"], "-", "-", f"[red]{row['error']}[/]", "-")
        else:
            table.add_row(
                row["name"],
                str(row["joints"]),
                f"{row['mass_kg']:.2f}",
                row["actuator_detail"],
                row["world"],
            )
    console.print(table)


def register(app: typer.Typer) -> None:
    app.command("robots")(robots)
