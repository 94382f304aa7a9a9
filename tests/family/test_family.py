"""Family models (SPEC 16): fit on members, save, load and mesh a new member; the guard's
fallback to the member's own start; a member outside the family refused in one line."""

from __future__ import annotations

import numpy as np
import pytest

from pinn_engine import job
from pinn_engine.errors import InputError
from pinn_engine.family import mesh as family_mesh
from pinn_engine.geometry.boundary import Boundary
from pinn_engine.settings import make_settings

SIZE = (21, 11)
EPOCHS = 40  # a few: the round trip, not the model's accuracy (benchmarks/family.py)


def channel(height: float, amplitude: float) -> np.ndarray:
    """A channel of length 3 with a bump of ``height`` on its floor and a roof waving by
    ``amplitude``, counter-clockwise from (0, 0)."""
    x = np.linspace(0.0, 3.0, 61)
    bottom = np.column_stack([x, height * np.exp(-(((x - 1.5) / 0.4) ** 2))])
    top = np.column_stack([x, 1 + amplitude * np.sin(2 * np.pi * x / 3)])[::-1]
    right = np.linspace(bottom[-1], top[0], 11)
    left = np.linspace(top[-1], bottom[0], 11)
    return np.vstack([bottom[:-1], right[:-1], top[:-1], left[:-1]])


def geometry(points: np.ndarray) -> job.Geometry:
    return job.Geometry(boundary=Boundary.from_points(points, source="channel"))


# a family of Winslow grids: its model's own Winslow steps make the round trip exact to a
# fraction of a degree in a few epochs (the default's quality grids need a longer fit)
SETTINGS = make_settings("pinn", size=SIZE, lattice=SIZE, objective="winslow")
TRAIN = [(h, a) for h in (0.1, 0.2, 0.3) for a in (0.02, 0.08)]


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    """A model fitted on six channels, saved."""
    members, targets = [], []
    for h, a in TRAIN:
        g = geometry(channel(h, a))
        member = job.family_member(SETTINGS, g)
        members.append(member)
        targets.append(job.member_target(member, job.run(SETTINGS, g)))
    model = job.fit_family_model(members, targets, "--size 21 11", epochs=EPOCHS)
    path = tmp_path_factory.mktemp("family") / "channels.pt"
    model.save(path)
    return path


def test_a_saved_model_meshes_a_new_member_as_its_own_run_would(fitted):
    """The round trip: the loaded model's grid of an unseen member has the member's own
    boundary nodes, no fold, and its own grid's quality (worst within 2 degrees, mean within
    0.5); the report says family and names the model's file."""
    g = geometry(channel(0.25, 0.05))
    own = job.run(SETTINGS, g)
    by_model = job.run(SETTINGS, g, family=fitted)
    a, b = own.grids[0], by_model.grids[0]
    for side in (np.s_[0], np.s_[-1], np.s_[:, 0], np.s_[:, -1]):
        np.testing.assert_allclose(b[side], a[side], atol=1e-12)
    q, ref = by_model.quality, own.quality
    assert q["folded_cells"] == 0
    assert q["worst_max_angle"] <= ref["worst_max_angle"] + 2
    assert q["mean_max_angle"] <= ref["mean_max_angle"] + 0.5
    training = by_model.report["training"]
    assert training["result"] == "family" and training["model"] == str(fitted)
    fd = by_model.data.GetFieldData()
    assert fd.GetAbstractArray("NetworkResult").GetValue(0) == "family"
    assert fd.GetAbstractArray("FamilyModel").GetValue(0) == str(fitted)


def test_a_folded_prediction_falls_back_to_the_members_start(fitted, monkeypatch):
    """The guard: a model grid with a folded cell gives the member's own start (its Winslow
    grid), with a warning that says so."""
    from pinn_engine.errors import grid_warnings
    from pinn_engine.family.model import FamilyModel

    real = FamilyModel.predict

    def folded(self, member):
        grid, info = real(self, member)
        grid = grid.copy()
        grid[5, 10], grid[5, 11] = grid[5, 11].copy(), grid[5, 10].copy()  # two nodes swapped
        return grid, info

    monkeypatch.setattr(FamilyModel, "predict", folded)
    monkeypatch.setattr(family_mesh, "DEFECT_STEPS", 0)  # no Winslow step to unfold it
    g = geometry(channel(0.25, 0.05))
    by_model = job.run(SETTINGS, g, family=fitted)
    elliptic = job.run(make_settings("elliptic", size=SIZE), g)
    assert by_model.report["training"]["result"] == "start"
    np.testing.assert_allclose(by_model.grids[0], elliptic.grids[0], atol=1e-9)
    warnings = [text for text, _ in grid_warnings(by_model.report, "cli")]
    assert any("family model" in text and "start" in text for text in warnings)


@pytest.mark.parametrize(
    "settings, words",
    [
        (make_settings("pinn", size=(31, 11)), "31 x 11"),
        (make_settings("elliptic", size=SIZE), "method elliptic"),
    ],
)
def test_a_member_outside_the_family_is_one_line(fitted, settings, words):
    """Other counts or other node-placing options: a one-line error naming both."""
    with pytest.raises(InputError, match=words) as err:
        job.run(settings, geometry(channel(0.2, 0.05)), family=fitted)
    assert "\n" not in str(err.value) and "outside the family" in str(err.value)


def test_a_body_is_outside_a_four_sided_family(fitted):
    from pinn_engine.bodies.airfoil import circle, load_body

    body = load_body(naca="0012", te="blunt")
    settings = make_settings("pinn", size=SIZE, topology="o")
    g = job.Geometry(body=body, far=circle(body, settings.farfield))
    with pytest.raises(InputError, match="O-grids of 21 x 11 nodes"):
        job.run(settings, g, family=fitted)


def test_members_of_other_counts_are_refused_at_the_fit():
    members = []
    for size in (SIZE, SIZE, (31, 11)):
        s = make_settings("pinn", size=size)
        members.append(job.family_member(s, geometry(channel(0.2, 0.05))))
    targets = [m.base for m in members]
    with pytest.raises(InputError, match="31 x 11"):
        job.fit_family_model(members, targets, epochs=1)


def test_a_model_file_that_is_no_family_model_is_one_line(tmp_path):
    bad = tmp_path / "bad.pt"
    bad.write_text("not a model")
    with pytest.raises(InputError, match="not a readable family model"):
        job.run(SETTINGS, geometry(channel(0.2, 0.05)), family=bad)
    assert family_mesh.KEPT_MODELS >= 1


# a family of node optima (the default objective's four-sided grids): the model's grid is
# polished by the member's own node optimisation and vouched for by its own ranking
DEFAULT = make_settings("pinn", size=SIZE, lattice=SIZE)


@pytest.fixture(scope="module")
def optima():
    """A model fitted on six channels' default grids (not saved: the round trip is above)."""
    members, targets = [], []
    for h, a in TRAIN:
        g = geometry(channel(h, a))
        member = job.family_member(DEFAULT, g)
        members.append(member)
        targets.append(job.member_target(member, job.run(DEFAULT, g)))
    return job.fit_family_model(members, targets, "--size 21 11")


def test_a_family_of_node_optima_is_polished_and_kept_without_its_start(optima):
    """The model of default grids: the linear branch, its member's grid polished by its own
    node optimisation, kept without solving its start, on its own boundary nodes, no fold,
    within the default's tolerances of its own default grid."""
    assert optima.polish > 0 and optima.report["ridge_components"] >= 1
    g = geometry(channel(0.25, 0.05))
    own = job.run(DEFAULT, g)
    by_model = job.run(DEFAULT, g, family=optima)
    training = by_model.report["training"]
    assert training["result"] == "family" and not training["start_solved"]
    assert training["polish_iterations"] == optima.polish
    a, b = own.grids[0], by_model.grids[0]
    for side in (np.s_[0], np.s_[-1], np.s_[:, 0], np.s_[:, -1]):
        np.testing.assert_allclose(b[side], a[side], atol=1e-12)
    q, ref = by_model.quality, own.quality
    assert q["folded_cells"] == 0
    assert q["worst_max_angle"] <= ref["worst_max_angle"] + 2
    assert q["mean_max_angle"] <= ref["mean_max_angle"] + 0.5


def test_a_model_grid_below_the_members_own_start_is_not_polished(optima, monkeypatch):
    """A family of node optima: a model's grid that ranks below the grid the member's own
    optimisation starts from (here a folded prediction) is not where the polish starts; the
    member's start is, and the grid kept ranks no worse than it: no fold, its own default
    grid's boundary nodes, within the check's bounds of that grid."""
    from pinn_engine.family.model import FamilyModel

    real = FamilyModel.predict

    def folded(self, member):
        grid, info = real(self, member)
        grid = grid.copy()
        grid[5, 10], grid[5, 11] = grid[5, 11].copy(), grid[5, 10].copy()  # two nodes swapped
        return grid, info

    monkeypatch.setattr(FamilyModel, "predict", folded)
    g = geometry(channel(0.25, 0.05))
    by_model = job.run(DEFAULT, g, family=optima)
    own = job.run(DEFAULT, g)
    training = by_model.report["training"]
    assert training["result"] == "family" and not training["start_solved"]
    assert "the model's grid ranked below it" in training["polished_against"]
    q, ref = by_model.quality, own.quality
    assert q["folded_cells"] == 0
    assert q["worst_max_angle"] <= ref["worst_max_angle"] + 2
    assert q["mean_max_angle"] <= ref["mean_max_angle"] + 0.5
    np.testing.assert_allclose(by_model.grids[0][0], own.grids[0][0], atol=1e-12)


def test_the_polish_leaps_to_the_own_runs_sharpest_stage_once_one_settles(optima, monkeypatch):
    """A family of node optima: the polish optimises the member's nodes from the model's grid
    at 2 degrees, and once that stage has settled at 1/8 degree alone (mesh.POLISH_SHARPENING:
    each a quarter of the one before, the last the own run's; the 1/2 stage between only
    after a stage that ran out of iterations), each stage settled."""
    from pinn_engine.quality import QUALITY_TAU
    from pinn_engine.starts import quality_start as qs

    stages = []
    real = qs.optimize_nodes

    def recorded(*args, **kwargs):
        stages.append((kwargs["tau"] / QUALITY_TAU, kwargs["settle"] is not None))
        return real(*args, **kwargs)

    monkeypatch.setattr(qs, "optimize_nodes", recorded)
    by_model = job.run(DEFAULT, geometry(channel(0.25, 0.05)), family=optima)
    assert by_model.report["training"]["result"] == "family"
    assert stages == [(2.0, True), (0.125, True)]


def _stages(grid: np.ndarray, iterations: int, settle, leap: bool) -> list[float]:
    """The temperatures (shares of QUALITY_TAU) of the stages quality_start.sharpened runs
    on ``grid`` at 2, 1/2 and 1/8 degree, at most ``iterations`` each."""
    from pinn_engine.quality import QUALITY_TAU
    from pinn_engine.starts import quality_start as qs

    stages = []
    real = qs.optimize_nodes
    with pytest.MonkeyPatch.context() as monkeypatch:
        monkeypatch.setattr(
            qs, "optimize_nodes", lambda *a, **k: stages.append(k["tau"]) or real(*a, **k)
        )
        ranking = qs.Ranking.of(grid, (), 1.0)
        qs.sharpened(grid, ranking, iterations, settle, (2.0, 1 / 2, 1 / 8), leap)
    return [tau / QUALITY_TAU for tau in stages]


def test_a_leaping_polish_runs_the_stages_between_only_after_one_out_of_iterations():
    """quality_start.sharpened with ``leap``: a stage that settled (a sheared box, its worst
    angle its fixed corners') is followed by the last alone, where without ``leap`` every
    stage runs; a stage that runs out of its iterations is followed by the next."""
    from pinn_engine.starts import quality_start as qs

    x, y = np.meshgrid(np.linspace(0, 1, 11), np.linspace(0, 1, 7))
    box = np.stack([x + 0.3 * y, y], -1)  # a sheared box: 106.7-degree corners, fixed
    settle = qs.Settle(50, 0.05, 0.25)
    assert _stages(box, 100, settle, leap=True) == [2.0, 0.125]
    assert _stages(box, 100, settle, leap=False) == [2.0, 0.5, 0.125]
    skewed = box.copy()
    skewed[3, 5] += (0.02, 0.03)
    assert _stages(skewed, 1, settle, leap=True) == [2.0, 0.5, 0.125]


def _settled(grid: np.ndarray, ranking, settle) -> tuple[np.ndarray, int]:
    """quality_start.optimize_nodes of ``grid`` (at most 100 iterations) stopped by
    ``settle``, and how many times it evaluated its objective."""
    from pinn_engine.starts import quality_start as qs

    calls = []
    real = qs.quality_loss
    with pytest.MonkeyPatch.context() as monkeypatch:
        monkeypatch.setattr(qs, "quality_loss", lambda *a: calls.append(1) or real(*a))
        return qs.optimize_nodes(grid, ranking, 100, settle=settle), len(calls)


def test_a_settled_polish_stops_early_and_never_ranks_below_its_start():
    """quality_start.optimize_nodes with a Settle: it stops once its window has not lowered
    the worst angle by the step (far fewer iterations than asked on a grid whose worst angle
    no interior node changes), and the state it returns ranks no worse than its start."""
    from pinn_engine.starts import quality_start as qs

    ni, nj = 11, 7
    x, y = np.meshgrid(np.linspace(0, 1, ni), np.linspace(0, 1, nj))
    grid = np.stack([x + 0.3 * y, y], -1)  # a sheared box: 73.3-degree corners, fixed
    grid[3, 5] += (0.02, 0.03)
    ranking = qs.Ranking.of(grid, (), 1.0)
    settled, calls = _settled(grid, ranking, qs.Settle(5, 0.05, 0.25))
    assert calls < 3 * 20
    assert ranking.key(ranking.quality(settled)) <= ranking.key(ranking.quality(grid))


def test_a_settled_polish_stops_at_its_held_corners_worst_angle():
    """quality_start.optimize_nodes with a Settle: where its best state's worst angle is that
    of a corner no interior node changes (a sheared box's, 106.7 degrees, every cell's), no
    state ranks better, and it stops there, long before its window of 50 iterations."""
    from pinn_engine.starts import quality_start as qs

    x, y = np.meshgrid(np.linspace(0, 1, 11), np.linspace(0, 1, 7))
    grid = np.stack([x + 0.3 * y, y], -1)  # a sheared box: 106.7-degree corners, fixed
    ranking = qs.Ranking.of(grid, (), 1.0)
    settled, calls = _settled(grid, ranking, qs.Settle(50, 0.05, 0.25))
    assert calls < 10
    corner = 180 - np.degrees(np.arctan2(1, 0.3))
    assert ranking.quality(settled)["worst_max_angle"] == pytest.approx(corner, abs=1e-3)


def test_a_model_grid_below_the_members_start_starts_the_polish_from_a_blend():
    """family.mesh.polish_start: a model's grid that ranks below the member's own start (a
    node moved past its neighbour: folded) gives way to the best ranked blend of the start
    towards it, here the one that puts the node back where the box has it; a model's grid
    that ranks no worse than the start is where the polish starts."""
    from pinn_engine.family.mesh import polish_start
    from pinn_engine.starts import quality_start as qs

    x, y = np.meshgrid(np.linspace(0, 1, 11), np.linspace(0, 1, 7))
    box = np.stack([x, y], -1)
    ranking = qs.Ranking.of(box, (), 1.0)
    begin, model = box.copy(), box.copy()
    begin[3, 5, 0] += 0.04  # a skewed start
    model[3, 5, 0] -= 0.16  # past its neighbour at -0.1: folded
    begun = ranking.quality(begin)
    start, share = polish_start(ranking, begin, begun, model)
    assert share == pytest.approx(0.2)
    np.testing.assert_allclose(start, box, atol=1e-12)
    assert polish_start(ranking, begin, begun, box)[1] == 1.0


# a family of O-grids under the default (its members' nodes optimised where that ranks
# better): the model's grid is the start of the member's own optimisation
BODY_SIZE = (65, 17)
SECTIONS = ("0010", "1412", "2412", "2415", "4412", "4415")


def naca(code: str) -> tuple:
    settings = make_settings("pinn", size=BODY_SIZE, topology="o", naca=code)
    return settings, job.geometry_from_files(settings, None)


@pytest.fixture(scope="module")
def sections():
    """A model fitted on six NACA O-grids' default grids."""
    members, targets = [], []
    for code in SECTIONS:
        settings, g = naca(code)
        member = job.family_member(settings, g)
        members.append(member)
        targets.append(job.member_target(member, job.run(settings, g)))
    return job.fit_family_model(members, targets, "--topology o --size 65 17")


@pytest.fixture(scope="module")
def unseen():
    """An unseen section of the family (NACA 3413): its settings, geometry and own run."""
    settings, g = naca("3413")
    return settings, g, job.run(settings, g)


def test_a_certified_body_grid_is_kept_without_its_members_optimisation(
    sections, unseen, monkeypatch
):
    """An O-grid family: the model's grid, kept without the member's own start (its
    elliptic grid) or optimisation (its worst angle within 2 degrees of the held first
    layer's, which bounds its own run's grid); the wall, first layer and far field are its
    own run's nodes, the seam one column, no fold, its own grid's quality within the
    check's bounds."""
    from pinn_engine.bodies import bodygrid
    from pinn_engine.starts import quality_start

    settings, g, own = unseen

    def not_called(*args, **kwargs):
        raise AssertionError("the member's elliptic grid or optimisation ran")

    monkeypatch.setattr(quality_start, "optimize_nodes", not_called)
    monkeypatch.setattr(bodygrid, "elliptic", not_called)
    by_model = job.run(settings, g, family=sections)
    training = by_model.report["training"]
    assert training["result"] == "family" and not training["start_solved"]
    assert training["polished_against"] == "family (not optimised: certified)"
    a, b = own.grids[0], by_model.grids[0]
    for rows in (np.s_[:2], np.s_[-1]):  # the wall and first layer, the far field
        np.testing.assert_allclose(b[rows], a[rows], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(b[:, -1], b[:, 0])  # the seam
    q, ref = by_model.quality, own.quality
    assert q["folded_cells"] == 0
    assert q["worst_max_angle"] <= ref["worst_max_angle"] + 2
    assert q["mean_max_angle"] <= ref["mean_max_angle"] + 0.5


def test_the_held_layer_bounds_a_body_grid_from_below(sections, unseen):
    """The certificate's premise: the member's own grid (its elliptic grid or that grid
    optimised) keeps its wall and first layer, those of its reference grid (the model's
    base), so its worst angle is at least theirs."""
    settings, g, own = unseen
    member = job.family_member(settings, g)
    np.testing.assert_array_equal(member.layout.reference[:2], own.grids[0][:2])
    assert own.quality["worst_max_angle"] >= family_mesh.held_worst(member.base) - 1e-9


@pytest.mark.slow  # a body family fitted, then each member's own run beside it
def test_a_body_family_polishes_as_its_members_own_run_chooses(sections, unseen, monkeypatch):
    """An O-grid family whose model's grids are not certified (here forced): the member's
    own choice (its elliptic grid, or that optimised where it ranks better), its
    optimisation started from the model's grid; the wall and far field are its own run's
    nodes, no fold, its own grid's quality within the check's bounds."""
    model = sections
    assert model.polish > 0 and model.report["polish_iterations"] == model.polish
    settings, g, own = unseen
    monkeypatch.setattr(family_mesh, "held_worst", lambda elliptic: -np.inf)
    by_model = job.run(settings, g, family=model)
    training = by_model.report["training"]
    assert training["result"] == "family"
    assert training["polished_against"] in ("elliptic", "optimized")
    a, b = own.grids[0], by_model.grids[0]
    np.testing.assert_allclose(b[0], a[0], atol=1e-12)  # the wall
    np.testing.assert_allclose(b[-1], a[-1], atol=1e-12)  # the far field
    q, ref = by_model.quality, own.quality
    assert q["folded_cells"] == 0
    assert q["worst_max_angle"] <= ref["worst_max_angle"] + 2
    assert q["mean_max_angle"] <= ref["mean_max_angle"] + 0.5


def test_a_body_model_grid_below_the_elliptic_grid_is_not_the_optimisations_start(
    sections, unseen, monkeypatch
):
    """A model's grid that ranks below the member's elliptic grid (here folded: two nodes
    swapped) is not where the optimisation starts: the member's own run's start and choice,
    so its own run's grid."""
    from pinn_engine.family.model import FamilyModel

    real = FamilyModel.predict

    def folded(self, member):
        grid, info = real(self, member)
        grid = grid.copy()
        grid[8, 30], grid[8, 31] = grid[8, 31].copy(), grid[8, 30].copy()
        return grid, info

    monkeypatch.setattr(FamilyModel, "predict", folded)
    monkeypatch.setattr(family_mesh, "held_worst", lambda elliptic: -np.inf)  # optimised
    settings, g, own = unseen
    by_model = job.run(settings, g, family=sections)
    assert by_model.report["training"]["result"] == "family"
    assert by_model.quality["folded_cells"] == 0
    assert by_model.quality["worst_max_angle"] == pytest.approx(
        own.quality["worst_max_angle"], abs=1e-3
    )
    assert by_model.quality["mean_max_angle"] == pytest.approx(
        own.quality["mean_max_angle"], abs=1e-3
    )


def ramp(height: float, apex: float) -> np.ndarray:
    """A channel of length 3 whose floor rises straight to a sharp apex of ``height`` at x =
    ``apex`` and falls again (three sharp vertices inside the bottom side)."""
    bottom = np.array(
        [[0, 0], [apex - 0.5, 0], [apex, height], [apex + 0.5, 0], [3, 0]], dtype=float
    )
    x = np.linspace(0.0, 3.0, 61)
    top = np.column_stack([x, np.ones_like(x)])[::-1]
    right = np.linspace(bottom[-1], top[0], 11)
    left = np.linspace(top[-1], bottom[0], 11)
    return np.vstack([bottom[:-1], right[:-1], top[:-1], left[:-1]])


def test_a_family_of_sharp_sided_domains_keeps_each_sharp_vertex_a_node():
    """Members whose sides turn sharply between their corners: the model's grid has a node on
    each sharp vertex, placed as the member's own run places it (its boundary nodes), and is
    written (the cover check refuses a grid that cuts one)."""
    members, targets = [], []
    for h in (0.15, 0.25, 0.35):
        for c in (1.2, 1.6):
            g = geometry(ramp(h, c))
            member = job.family_member(DEFAULT, g)
            members.append(member)
            targets.append(job.member_target(member, job.run(DEFAULT, g)))
    model = job.fit_family_model(members, targets, "--size 21 11")
    g = geometry(ramp(0.3, 1.43))
    own = job.run(DEFAULT, g)
    by_model = job.run(DEFAULT, g, family=model)
    assert by_model.report["training"]["result"] == "family"
    bottom = by_model.grids[0][0]
    np.testing.assert_allclose(bottom, own.grids[0][0], atol=1e-12)
    for vertex in ((0.93, 0.0), (1.43, 0.3), (1.93, 0.0)):
        assert np.linalg.norm(bottom - vertex, axis=1).min() < 1e-12
    assert by_model.quality["folded_cells"] == 0
    assert by_model.quality["worst_max_angle"] <= own.quality["worst_max_angle"] + 2


@pytest.mark.slow  # seven C-grids' own runs (about 1 s each) and a fit
def test_a_c_grid_whose_polish_from_the_model_fails_its_choice_gets_its_own_runs_grid(
    monkeypatch,
):
    """A C-grid family: where the optimisation from the model's grid fails the member's
    choice (its elliptic grid returned; here forced), the member's own run's choice from its
    elliptic grid decides, so its grid is its own run's."""
    from pinn_engine.starts import quality_start

    members, targets = [], []
    for code in SECTIONS:
        settings = make_settings("pinn", size=BODY_SIZE, topology="c", naca=code)
        g = job.geometry_from_files(settings, None)
        member = job.family_member(settings, g)
        members.append(member)
        targets.append(job.member_target(member, job.run(settings, g)))
    model = job.fit_family_model(members, targets, "--topology c --size 65 17")
    settings = make_settings("pinn", size=BODY_SIZE, topology="c", naca="2412")
    g = job.geometry_from_files(settings, None)
    own = job.run(settings, g)
    assert own.report["training"]["start"] == "optimized"
    real = quality_start.body_quality_start

    def failing(elliptic, seam, held, begin=None):
        return (elliptic, "elliptic") if begin is not None else real(elliptic, seam, held)

    monkeypatch.setattr(quality_start, "body_quality_start", failing)
    monkeypatch.setattr(family_mesh, "held_worst", lambda elliptic: -np.inf)  # optimised
    by_model = job.run(settings, g, family=model)
    assert by_model.report["training"]["polished_against"] == "optimized"
    np.testing.assert_allclose(by_model.grids[0], own.grids[0], atol=1e-9)


@pytest.mark.parametrize("topology", ["o", "c"])
@pytest.mark.parametrize("optimised", [True, False])
def test_a_body_model_grid_keeps_the_nodes_its_own_run_never_moves(topology, optimised):
    """A body's model grid takes its start's wall, far field and a C-grid's outflow columns
    exactly, its first layer too where its own run optimises its nodes (which hold it; a
    trained network's correction moves it), and an O-grid's seam is one column."""
    from pinn_engine.family.members import Member
    from pinn_engine.family.model import _held

    rng = np.random.default_rng(0)
    base = rng.random((6, 9, 2))
    grid = base + 1e-3 * rng.random(base.shape)
    if topology == "o":  # column ni - 1 repeats column 0
        base[:, -1], grid[:, -1] = base[:, 0], grid[:, 0]
    member = Member("body", topology, base, None, "test")
    held = _held(grid.copy(), member, optimised)
    np.testing.assert_array_equal(held[0], base[0])
    np.testing.assert_array_equal(held[-1], base[-1])
    np.testing.assert_array_equal(held[1, 1:-1], (base if optimised else grid)[1, 1:-1])
    if topology == "o":
        np.testing.assert_array_equal(held[:, -1], held[:, 0])
    else:
        np.testing.assert_array_equal(held[:, [0, -1]], base[:, [0, -1]])
    np.testing.assert_array_equal(held[2:-1, 1:-1], grid[2:-1, 1:-1])
