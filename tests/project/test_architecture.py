"""The recipes of docs/architecture.md, each done once: a loss term, a block kind, an option and
a route added without touching the trainer or the other routes."""

from __future__ import annotations

import ast
import itertools
import re
import subprocess
import sys
import tokenize
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import torch
from helpers import EXAMPLES, ROOT

from pinn_engine import job
from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import Boundary
from pinn_engine.io import export
from pinn_engine.io.export.algorithm import PARAVIEW_FORMATS
from pinn_engine.io.export.registry import Format, register
from pinn_engine.io.fileio import read_boundary_points
from pinn_engine.io.vtkgrid import structured_grid
from pinn_engine.kinds.four_sided import problem as quad
from pinn_engine.neural import trainer
from pinn_engine.routes.algorithm import PinnMeshAlgorithm
from pinn_engine.routes.cli import build_parser, main
from pinn_engine.routes.cli.parser import option_flags
from pinn_engine.settings import (
    Interval,
    Options,
    make_settings,
    option_constraints,
)

PACKAGE = ROOT / "pinn_engine"


def test_recipe_loss_term(monkeypatch):
    """A new term (the mean squared network output, weighted 10) returned by the four-sided
    block's ``terms`` and weighed in its ``loss``: the unchanged trainer records it in the
    history and minimises it."""
    terms, loss = quad.QuadProblem.terms, quad.QuadProblem.loss

    def with_smallness(self, x, base, bx, by):
        out = terms(self, x, base, bx, by)
        out["smallness"] = self.net(x).pow(2).sum(dim=-1).mean()
        return out

    def weighted(self, t, lambda1):
        return loss(self, t, lambda1) + 10.0 * t["smallness"]

    monkeypatch.setattr(quad.QuadProblem, "terms", with_smallness)
    monkeypatch.setattr(quad.QuadProblem, "loss", weighted)
    ring = Boundary.from_points(read_boundary_points(EXAMPLES / "fig2.vtp"))
    settings = make_settings("pinn", warm_start="none", adam_epochs=200, lbfgs_iterations=0)
    model = quad.train(ring, [], settings)
    history = model.history["smallness"]
    assert len(history) == 200 and history[-1] < 0.5 * history[0]


class _GradedLine:
    """A toy block kind: nodes x(s) on [0, 1] with x(0) = 0, x(1) = 1 built in (x = s +
    s (1 - s) N(s)), whose cells grow by a constant ratio: x'' = log(RATIO) x'."""

    RATIO = 4.0
    anneals = False

    def __init__(self, settings) -> None:
        torch.manual_seed(settings.seed)
        self.net = torch.nn.Sequential(
            torch.nn.Linear(1, 16, dtype=torch.float64),
            torch.nn.Tanh(),
            torch.nn.Linear(16, 1, dtype=torch.float64),
        )
        self.settings = settings

    def x(self, s: torch.Tensor) -> torch.Tensor:
        return s + s * (1 - s) * self.net(s)

    def epoch_batch(self, epoch: int) -> tuple:
        return (torch.rand(64, 1, dtype=torch.float64, requires_grad=True),)

    def lbfgs_batch(self) -> tuple:
        return (torch.linspace(0, 1, 64, dtype=torch.float64)[:, None].requires_grad_(),)

    def terms(self, s: torch.Tensor) -> dict[str, torch.Tensor]:
        x = self.x(s)
        dx = torch.autograd.grad(x.sum(), s, create_graph=True)[0]
        ddx = torch.autograd.grad(dx.sum(), s, create_graph=True)[0]
        return {"eqns": (ddx - np.log(self.RATIO) * dx).pow(2).mean()}

    def loss(self, terms, lambda1):
        return terms["eqns"]

    def evaluate(self, batch):
        return trainer.AutogradEvaluation(self, batch)

    def weights(self, lambda1):
        return {}

    def grid(self) -> np.ndarray:
        with torch.no_grad():
            return self.x(torch.linspace(0, 1, 11, dtype=torch.float64)[:, None]).numpy()


def test_recipe_block_kind():
    """The toy kind trains with the unchanged trainer and guard: the guard keeps the trained
    state (its growth ratio is nearer the target) and reports the node move."""
    settings = make_settings("pinn", lbfgs_iterations=60)
    problem = _GradedLine(settings)

    def growth(grid: np.ndarray) -> dict:  # x' grows by RATIO over [0, 1]: RATIO^0.9 here
        cells = np.diff(grid[:, 0])
        return {"error": float(np.abs(cells[-1] / cells[0] - _GradedLine.RATIO**0.9))}

    guard = trainer.Guard(
        problem.net,
        problem.grid,
        growth,
        lambda q, kept: q["error"] <= kept["error"],
        growth(problem.grid()),
        1.0,
    )
    with trainer.training_process(torch.device("cpu")):
        history, info = trainer.fit(problem, settings, guard)
    assert info["result"] == "network" and info["largest_node_move"] > 0.05
    assert info["guard"]["kept"]["error"] < 0.01
    assert history["eqns"][-1] < 1e-3 * history["eqns"][0]


@pytest.mark.parametrize("name", sorted(option_constraints()))
def test_recipe_option(name, capsys):
    """Every setting of the constraint table reaches every route: the command line's flag
    (out-of-range values refused in one line naming it), the VTK algorithm's SetSetting."""
    rule = option_constraints()[name]
    flags = {a.dest: a.option_strings for a in build_parser()._actions}
    assert name in flags
    alg = PinnMeshAlgorithm()
    good = rule.values[0] if isinstance(rule, Options) else None
    if isinstance(rule, Interval):
        good = rule.kind(rule.low)
    if good is not None and name not in ("method", "preset"):
        alg.SetSetting(name, good)
        assert alg._overrides[name] == good
    for flag in flags[name] if isinstance(rule, Interval) else ():  # SPEC 5's and the one name
        bad = rule.low - 1
        assert main([str(EXAMPLES / "fig2.vtp"), flag, str(bad), "-o", "x.vts"]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and option_flags()[name] in err


def test_recipe_route(tmp_path):
    """A route of its own in a few lines (numpy points in, numpy grid out) gives the command
    line's grid for the same options."""

    def numpy_route(points: np.ndarray, size: tuple[int, int], **options) -> np.ndarray:
        settings = make_settings(options.pop("method", "pinn"), lattice=size, size=size, **options)
        ring = Boundary.from_points(points, source="points")
        return job.run(settings, job.Geometry(boundary=ring)).grids[0]

    points = read_boundary_points(EXAMPLES / "fig2.vtp")
    grid = numpy_route(points, (21, 11), method="elliptic")
    out = tmp_path / "g.vts"
    assert main([str(EXAMPLES / "fig2.vtp"), "--method", "elliptic", "--size", "21", "11",
                 "-o", str(out), "--quiet"]) == 0  # fmt: skip
    import pyvista as pv

    expected = pv.read(out).points[:, :2].reshape(11, 21, 2)
    np.testing.assert_allclose(grid, expected, atol=1e-12)


def test_recipe_format(tmp_path, monkeypatch):
    """The formats register themselves (in --format's order); a suffix taken by another key
    is refused; a format registered once is written by ``export.write``, taken by --format
    and named by the multi-block writer's refusal, with no table of its own anywhere."""
    grid = structured_grid(np.stack(np.meshgrid(np.arange(5.0), np.arange(4.0)), axis=-1))
    assert list(export.FORMATS) == ["vts", "vtk", "xyz", "cgns", "su2", "msh", "openfoam"]
    assert set(PARAVIEW_FORMATS) == {"xyz", "cgns", "su2", "msh", "openfoam"}
    with pytest.raises(ValueError, match="clashes"):
        register(replace(export.FORMATS["su2"], key="su2b"))

    def write_toy(block, path: Path) -> None:
        path.write_text(f"{block.ni} {block.nj}\n")

    toy = Format("toy", ".toy", "a toy format", False, name="Toy", block=write_toy)
    monkeypatch.setitem(export.FORMATS, "toy", toy)
    assert export.write(grid, tmp_path / "g.toy").read_text() == "5 4\n"
    action = next(a for a in build_parser()._actions if a.dest == "format")
    assert "toy" in action.choices and list(action.choices)[-1] == "toy"
    with pytest.raises(InputError, match=r"--format openfoam, not as a toy format"):
        export.blocks_format(tmp_path / "g.toy", None, None)


def _layers() -> list[set[str]]:
    """The layers of docs/architecture.md's picture, top first: each line of its first text
    block that starts one space in names the units (modules or sub-packages) of one layer."""
    text = (ROOT / "docs" / "architecture.md").read_text()
    picture = text.split("```text\n", 1)[1].split("```", 1)[0]
    units = {p.stem for p in PACKAGE.glob("*.py")} | {
        p.parent.name for p in PACKAGE.glob("*/__init__.py")
    }
    layers = []
    for line in picture.splitlines():
        if line.startswith(" ") and not line.startswith("  "):
            words = [w.rstrip("/") for w in line.split()]
            layers.append(set(itertools.takewhile(lambda w: w in units, words)))
    return layers


def _imports(path: Path) -> list[tuple[int, str]]:
    """(line, unit) of every import of the package's own units in ``path``, at module level
    or inside functions alike (a lazy import is still an arrow of the picture)."""
    return [(line, name.split(".")[1]) for line, name in _modules(path) if "." in name]


def test_imports_follow_the_architecture_picture():
    """Every unit is on one layer of the picture, and imports only its own modules, units
    of lower layers, or (on the ground floor) its neighbours: no arrow runs up or across."""
    layers = _layers()
    level = {unit: k for k, layer in enumerate(layers) for unit in layer}
    ground = len(layers) - 1
    units = {p.stem for p in PACKAGE.glob("*.py")} | {
        p.parent.name for p in PACKAGE.glob("*/__init__.py")
    }
    assert units - {"__init__"} == set(level), "units missing from the picture or stale there"
    upward = []
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE).parts
        here = rel[0].removesuffix(".py")
        if here == "__init__":
            continue
        for line, unit in _imports(path):
            if unit not in level or unit == here:
                continue
            if level[unit] < level[here] or (level[unit] == level[here] != ground):
                upward.append(f"pinn_engine/{'/'.join(rel)}:{line} imports {unit}")
    assert not upward, f"imports against docs/architecture.md's picture: {upward}"


# What a route (the command line, its batches, the VTK algorithms, pyvista, the ParaView
# plugin) may import of the package: the job and its settings and outcome, inputs and outputs
# (io, the airfoil reader, the plane of a curve), the messages, and the routes themselves
ROUTE_IMPORTS = (
    "pinn_engine.job", "pinn_engine.settings", "pinn_engine.result",
    "pinn_engine.errors", "pinn_engine.io", "pinn_engine.patchnames", "pinn_engine.heap",
    "pinn_engine.lazy",
    "pinn_engine._version", "pinn_engine.__version__", "pinn_engine.geometry.plane",
    "pinn_engine.bodies.airfoil", "pinn_engine.routes", "pinn_engine.batch",
)  # fmt: skip
ROUTES = ("pinn_engine/routes", "pinn_engine/batch", "pinn_engine/command.py", "plugin")


def _modules(path: Path) -> list[tuple[int, str]]:
    """(line, module) of every import of the package in ``path``, wherever it stands."""
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [f"{node.module}.{a.name}" for a in node.names]
            if node.module != "pinn_engine":
                names = [node.module]
        elif isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        else:
            continue
        out += [(node.lineno, n) for n in names if n.split(".")[0] == "pinn_engine"]
    return out


def test_no_route_runs_a_kind_of_its_own():
    """The routes mesh only through ``job.run``: none imports a domain kind's pipeline
    (kinds/, blocks/, multiblock/, hexa/, ...), so none can call one or
    decide a kind by itself."""
    paths = []
    for route in ROUTES:
        top = ROOT / route
        paths += sorted(top.rglob("*.py")) if top.is_dir() else [top]
    assert len(paths) > 20
    stray = [
        f"{path.relative_to(ROOT)}:{line} imports {module}"
        for path in paths
        for line, module in _modules(path)
        if not any(module == a or module.startswith(a + ".") for a in ROUTE_IMPORTS)
    ]
    assert not stray, f"routes that reach past the job: {stray}"


FIRST_IMPORT = """
import importlib, pathlib, sys, warnings
warnings.simplefilter("ignore")
failed = []
for path in sorted(pathlib.Path("pinn_engine").rglob("*.py")):
    if path.name == "__main__.py":
        continue
    name = ".".join(path.with_suffix("").parts).removesuffix(".__init__")
    for loaded in [m for m in sys.modules if m.split(".")[0] == "pinn_engine"]:
        del sys.modules[loaded]
    try:
        importlib.import_module(name)
    except Exception as exc:
        failed.append(f"{name}: {exc!r}")
print("\\n".join(failed))
"""


@pytest.mark.slow
def test_every_module_imports_first():
    """Each module imports in a fresh package, whichever is imported first: no import
    circle hides behind the order in which the routes happen to import them."""
    run = subprocess.run(
        [sys.executable, "-c", FIRST_IMPORT], cwd=ROOT, capture_output=True, text=True, check=True
    )
    assert run.stdout.strip() == ""


COMMENT_BLOCK_LINES = 5  # the longest run of comment lines: what a value means, not its history
HISTORY = re.compile(r"[Ii]ssues? \d|#\d{2}|\bcommit\b|\([0-9a-f]{7,40}\)")


def _comments(path: Path) -> list[tuple[int, str]]:
    """(line, text) of every comment token of a Python file."""
    with path.open("rb") as f:
        tokens = tokenize.tokenize(f.readline)
        return [(t.start[0], t.string) for t in tokens if t.type == tokenize.COMMENT]


@pytest.mark.parametrize("folder", ["pinn_engine", "tests", "benchmarks"])
def test_no_comment_or_docstring_cites_an_issue_or_a_commit(folder):
    """Comments and docstrings of the package, the tests and the benchmarks say what is
    meant, checked or measured now."""
    cited = []
    for path in sorted((ROOT / folder).rglob("*.py")):
        tree = ast.parse(path.read_text())
        texts = _comments(path) + [
            (node.body[0].lineno, ast.get_docstring(node) or "")
            for node in ast.walk(tree)
            if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef)
        ]
        cited += [f"{path.relative_to(ROOT)}:{line}" for line, s in texts if HISTORY.search(s)]
    assert not cited, f"history belongs in commit messages and docs/tuning.md: {cited}"


def test_comment_blocks_are_short():
    long = []
    for path in sorted(PACKAGE.rglob("*.py")):
        lines = [line for line, text in _comments(path)]
        source = path.read_text().splitlines()
        whole = [n for n in lines if source[n - 1].lstrip().startswith("#")]
        run = 1
        for before, n in zip(whole, whole[1:]):
            run = run + 1 if n == before + 1 else 1
            if run == COMMENT_BLOCK_LINES + 1:
                long.append(f"{path.relative_to(ROOT)}:{n - COMMENT_BLOCK_LINES}")
    assert not long, f"comment blocks of more than {COMMENT_BLOCK_LINES} lines: {long}"


def test_tests_import_their_helpers_not_conftest():
    """Shared values and functions live in tests/helpers.py; conftest.py is pytest's own."""
    pattern = re.compile(r"^\s*(from|import) conftest\b", re.M)
    tests = sorted((ROOT / "tests").rglob("*.py"))
    importing = [str(p.relative_to(ROOT)) for p in tests if pattern.search(p.read_text())]
    assert not importing, f"import these from helpers instead of conftest: {importing}"


# the test folders that are not a package of pinn_engine, each with its one job
TEST_FOLDERS_BESIDE_PACKAGES = {
    "core": "the top-level modules of pinn_engine",
    "project": "the repository's own checks: docs, architecture, wheel, experiments",
    "paraview": "a real ParaView: pvpython scripts and the GUI under Xvfb",
}


def test_tests_are_grouped_by_package():
    """Each test file sits in the folder of the package it tests (docs/testing.md)."""
    packages = {p.parent.name for p in PACKAGE.glob("*/__init__.py")}
    allowed = packages | set(TEST_FOLDERS_BESIDE_PACKAGES)
    tests = sorted((ROOT / "tests").rglob("test_*.py"))
    misplaced = [
        str(p.relative_to(ROOT))
        for p in tests
        if len(p.relative_to(ROOT / "tests").parts) < 2
        or p.relative_to(ROOT / "tests").parts[0] not in allowed
    ]
    assert tests and not misplaced, f"move these into tests/<package>/: {misplaced}"
