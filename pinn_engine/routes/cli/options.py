"""The command line's options as a run's settings: ranges refused in the option's words, and
options a domain kind does not take (``job.OPTIONS``) refused by their flags."""

from __future__ import annotations

import argparse
import functools

from pinn_engine.errors import PinnMeshError
from pinn_engine.routes.cli.parser import build_parser, option_flags
from pinn_engine.routes.names import cli_option
from pinn_engine.settings import (
    DEVICE_NAMES,
    NEURAL,
    Settings,
    make_settings,
    option_constraints,
    setting_problem,
    size_problem,
)

# What every kind's run takes: its input, where its output goes and in which format, the
# report, quiet
ROUTE_OPTIONS = frozenset({"boundary", "output", "format", "report", "quiet"})


@functools.cache
def _defaults() -> dict:
    """Each option's default as the parser gives it (built once a process: a batch worker
    asks for every case)."""
    return vars(build_parser().parse_args([]))


def given_options(args: argparse.Namespace) -> list[str]:
    """The parsed names (dests) of the options given a value other than their default."""
    defaults = _defaults()
    return [dest for dest, value in vars(args).items() if value != defaults.get(dest)]


def refuse_options(args: argparse.Namespace, options, refusal: str) -> None:
    """Refuse the first option given (by its one name) of ``options``: ``refusal`` with its
    flag for ``{}``."""
    flags = option_flags()
    for dest in given_options(args):
        if cli_option(dest) in options:
            raise PinnMeshError(refusal.format(flags.get(dest, dest)))


def refuse_others(args: argparse.Namespace, kind: str, refusal: str) -> None:
    """Refuse the first option given that the domain ``kind`` does not take (``job.OPTIONS``
    and ``ROUTE_OPTIONS``): ``refusal`` with its flag for ``{}``."""
    from pinn_engine.job import OPTIONS

    takes = OPTIONS[kind] | ROUTE_OPTIONS
    others = {cli_option(dest) for dest in vars(args)} - takes
    refuse_options(args, others, refusal)


def check_options(args: argparse.Namespace) -> None:
    """Refuse option values that are out of range, with a message naming the option, and
    a --report or --png path that cannot be written (before any meshing)."""
    from pinn_engine.io.fileio import check_writable

    for extra in (args.report, args.png):
        if extra:
            check_writable(extra)
    problem = size_problem(tuple(args.size))
    if problem:
        raise PinnMeshError(f"--size {' '.join(map(str, args.size))}: {problem}")
    flags = option_flags()
    for name in option_constraints():  # each range, named by the option that set it
        value = getattr(args, name, None)
        problem = setting_problem(name, value) if value is not None else None
        if problem and name in flags:
            raise PinnMeshError(f"{flags[name]} {value}: {problem}")
    if args.device is not None:
        if not DEVICE_NAMES.match(args.device):
            raise PinnMeshError(f"--device {args.device!r}: use auto, cpu, cuda or cuda:N")
        if args.device.startswith("cuda") and args.method in NEURAL:
            import torch

            if not torch.cuda.is_available():
                raise PinnMeshError(
                    f"--device {args.device}: no CUDA device is available; use --device cpu or auto"
                )


def read_adapt_field(args: argparse.Namespace):
    """The field of ``--adapt FILE:ARRAY`` (``adapt.Field``), or None without it."""
    if not getattr(args, "adapt", None):
        return None
    from pinn_engine.job import read_field

    return read_field(args.adapt)


def settings_from(
    args: argparse.Namespace, size: tuple[int, ...] = (), kind: str | None = None
) -> Settings:
    """The settings of the command line's options for a grid of ``size`` nodes (() for
    multi-block) of ``kind`` (None: the one they describe, ``settings.settings_kind``), with
    a settings error as a one-line command-line error."""
    skip = ("method", "preset")  # given first: the preset is the base the others override
    options = {k: getattr(args, k) for k in option_constraints() if k not in skip}
    try:
        return make_settings(
            args.method,
            args.preset,
            kind,
            lattice=size if len(size) == 2 else None,
            size=size,
            spacing=args.spacing,
            orthogonal=args.orthogonal,
            device=args.device,
            **options,
        )
    except ValueError as exc:
        raise PinnMeshError(str(exc)) from exc
