"""``diffsense describe [KIND] [--parts ...] [--option k=v ...]``: what a scene takes and gives.

Without a kind it lists the sensor kinds; with one it prints the scene's parts, static options
(default and allowed values), parameters (unit, default, domain, the part they belong to) and
outputs. Error messages about unknown parameters point here.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import List, Optional

import typer
from rich.text import Text

from diffsense.cli.output import EXIT_BAD_INPUT, Reporter, clip, fmt, write_json
from diffsense.cli.state import reporter_from


def _option_value(name: str, text: str, allowed):
    """The allowed value whose text is ``text`` (so ``swerling=1`` gives the integer 1)."""
    from diffsense.design.spec.common import closest

    for value in allowed:
        if str(value) == text:
            return value
    names = [str(v) for v in allowed]
    raise typer.BadParameter(f"option {clip(name)!r} takes one of {names}; got {clip(text)!r}{closest(text, names)}",
                             param_hint="--option")


def _scene(kind: str, parts: str, options: List[str]):
    """The scene named on the command line; an unknown kind, part, option or option value is a
    usage error with up to three close names. Parts and options that the chain rejects together
    are left to :func:`describe` (the scene is not validated here)."""
    from diffsense.design.spec.common import closest
    from diffsense.scene import CHAINS, Scene

    if kind not in CHAINS:
        raise typer.BadParameter(f"unknown sensor kind {clip(kind)!r}{closest(kind, CHAINS)}; kinds: {sorted(CHAINS)}",
                                 param_hint="KIND")
    chain = CHAINS[kind]
    opts = {}
    for item in options:
        if "=" not in item:
            raise typer.BadParameter(f"write KEY=VALUE; got {clip(item)!r}", param_hint="--option")
        key, value = (s.strip() for s in item.split("=", 1))
        if key not in chain.options:
            raise typer.BadParameter(f"unknown option {clip(key)!r} of a {kind}{closest(key, chain.options)}; "
                                     f"options: {', '.join(sorted(chain.options))}", param_hint="--option")
        opts[key] = _option_value(key, value, chain.options[key][1])
    names = [p.strip() for p in parts.split(",") if p.strip()]
    for name in names:
        if name not in chain.parts:
            raise typer.BadParameter(f"unknown part {clip(name)!r} of a {kind}{closest(name, chain.parts)}; "
                                     f"parts: {', '.join(chain.parts)}", param_hint="--parts")
    return Scene(kind, names, opts)


def _parts_needed(scene, reason: str) -> str:
    """One line for a scene that holds too few parts to have parameters and outputs: why (the
    chain's ``reason``) and a ``diffsense describe`` command with one part that completes it."""
    from diffsense.errors import DomainError
    from diffsense.scene import CHAINS, Scene, chain_for, describe_command

    reason = re.sub(rf"^{re.escape(scene.sensor)} scene(?: \([^)]*\))?: ", "", reason)
    example = None
    for part in CHAINS[scene.sensor].parts:
        candidate = Scene(scene.sensor, [part], dict(scene.options))
        try:
            chain_for(candidate)
        except DomainError:
            continue
        example = candidate
        break
    how = f", e.g. '{describe_command(example)}'" if example is not None else ""
    return (f"parameters and outputs depend on the parts: a {scene.sensor} scene {reason}; "
            f"name the parts with --parts a,b{how}")


def _print_kinds(reporter: Reporter) -> None:
    from diffsense.scene import CHAINS

    reporter.table("Sensor kinds (diffsense describe KIND for one)", ("kind", "what it models"),
                   [(k, CHAINS[k].description) for k in sorted(CHAINS)])


def _print_scene(d: dict, reporter: Reporter) -> None:
    reporter.out.print(Text.assemble((d["sensor"], "bold"), f": {d['description']}"))
    reporter.table("Parts (add with --parts a,b)", ("part", "in scene", "what it adds"),
                   [(k, "yes" if v["in_scene"] else "", v["description"]) for k, v in d["parts"].items()])
    reporter.table("Options (set with --option KEY=VALUE)", ("option", "value", "default", "allowed"),
                   [(k, str(v["value"]), str(v["default"]), ", ".join(map(str, v["values"])))
                    for k, v in d["options"].items()])
    if "parameters" not in d:
        reporter.info(d["needs"], wrap=False)
        return
    rows = []
    for name, p in d["parameters"].items():
        default = "required" if p["default"] is None else fmt(p["default"])
        rows.append((name, p["unit"], default, p["domain"], p["part"] or "", p["doc"]))
    reporter.table("Parameters", ("parameter", "unit", "default", "domain", "part", "meaning"), rows)
    reporter.table("Outputs", ("output", "unit", "meaning"), [(k, v["unit"], v["doc"]) for k, v in d["outputs"].items()])


def describe(
    ctx: typer.Context,
    kind: Optional[str] = typer.Argument(None, help="Sensor kind (radar, lidar, sonar, radiometer, infrared, ultrasonic)."),
    parts: str = typer.Option("", "--parts", help="Comma-separated scene parts, e.g. rain,multipath."),
    option: List[str] = typer.Option([], "--option", help="A static option KEY=VALUE (repeatable), e.g. swerling=1."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the description as JSON here."),
    force: bool = typer.Option(False, "--force", help="Replace a --json file that diffsense did not write."),
):
    """List the sensor kinds, or what one scene takes: parts, options, parameters (unit, default,
    domain) and outputs. A kind whose scenes need a part (a sonar needs a noise or reverberation
    part) is described without parts by its parts and options, and a line saying how to name
    them."""
    from diffsense.errors import DomainError
    from diffsense.scene import chain_for, describe as describe_scene, describe_kind

    reporter = reporter_from(ctx)
    if kind is None:
        _print_kinds(reporter)
        return
    scene = _scene(kind, parts, option)
    try:
        chain_for(scene)
    except DomainError as exc:
        if scene.parts:  # parts named together that the chain rejects: bad input
            reporter.error(str(exc))
            raise typer.Exit(code=EXIT_BAD_INPUT)
        d = dict(describe_kind(scene), needs=_parts_needed(scene, str(exc)))
    else:
        d = describe_scene(scene)
    _print_scene(d, reporter)
    write_json(d, json_out, reporter, force=force)
