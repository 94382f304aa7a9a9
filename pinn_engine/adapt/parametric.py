"""The adaptive equations of SPEC 14 solved in the unadapted grid's own parameter space.

Each block's unadapted grid is a fold-free map x = X(u, v) from its logical lattice
(u = i, v = j), bilinear in every cell. The adapted grid is X(s(i, j)): new logical
positions s on the block's lattice, found from Winslow's variable-diffusion equations
(Winslow 1981) posed in that parameter space ("adaptation in computational space": the
diffusion tensor D of the monitor, :func:`diffusion_tensor`, pulled back through X to the
uniform lattice as K and K', :func:`own_diffusion`):

    div_u( K grad_u xi ) = 0,   div_u( K' grad_u eta ) = 0,   (the adaptive equations)

solved for the computational coordinates (xi, eta)(u, v) on a lattice ``REFINE`` times
finer than the block's (the monitor is resolved inside a cell), xi and eta given on the
block's sides, then inverted: s(i, j) is the (u, v) where (xi, eta) = (i, j). With D
constant the solution is xi = u, eta = v exactly (a linear function is discrete-harmonic),
so the unadapted grid, its gradings, wall spacings and angles, is where adaptation starts
from and what it keeps where the monitor is flat. The equations are linear in (xi, eta)
for a given D (a function of the unadapted grid's points, not of the adapted ones): one
sparse solve a block and coordinate, no Picard steps. Their finite-element operator has
non-negative edge weights on a triangulation of the block's rectangle (:func:`_stiffness`),
so the discrete map is one-to-one where both coordinates share them (Tutte's embedding;
Floater 2003, "One-to-one piecewise linear mappings over triangulations"); the guard checks
every grid for the rest.

A block's sides (interfaces, a C-grid's wake cut, an O-grid's seam) take the
one-dimensional form of the same equations, d(xi)/du / (s^T D s) constant between the
nodes that stay (s the side's direction); a boundary piece takes the block solve's natural
condition. Nodes slide along their own side (a boundary piece's spline, an interface or
cut's own polyline, the same positions from both sides), and the side's xi is the block's
boundary values.

A multi-block grid's blocks may be solved joined instead (``joined``,
:mod:`~pinn_engine.adapt.joined`: in the plane, interfaces and junctions inside the domain
as interior nodes); its boundary pieces then take the one-dimensional form, as interfaces
do here."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix, csr_matrix
from scipy.sparse.linalg import splu

from pinn_engine.adapt.joined import Joined
from pinn_engine.adapt.monitor import (
    cell_areas,
    curvature_diffusion,
    curvature_intensity,
    diffusion_tensor,
    gradient_size,
    gradient_tensor,
    hessian_tensor,
    principal_direction,
    shear_cap,
    slipped,
    to_nodes,
)
from pinn_engine.adapt.nodes import NodeGraph
from pinn_engine.adapt.pieces import Solved, pieces_of

REFINE = 4  # sub-cells a side of an unadapted cell: a front a cell wide is seen inside it
# refined nodes at most over all blocks (a sparse factorisation of this size takes about a
# second; a 40 000-cell grid solves on its own lattice, a 6 400-cell one at 3 sub-cells)
MAX_REFINED = 100_000
# the monitor's smoothing passes a sub-cell: the physical-space solve's two passes of the
# unadapted grid's cells, kept as wide
SMOOTHING_PER_CELL = 2
INSIDE_TOL = 1e-9  # a target on a triangle's edge counts as inside it (rounding)
# the strength at which the curvature metric's intensity is Huang's alpha (the error
# bound's own balance of the feature and the bulk): the default strength
CURVATURE_STRENGTH = 20.0
SYMMETRIC = {"SymmetricMode": True}  # SuperLU's pivoting for a symmetric matrix


def refinement(graph: NodeGraph) -> int:
    """Sub-cells a cell side: ``REFINE``, fewer where the refined lattices would pass
    ``MAX_REFINED`` nodes."""
    cells = sum((i.shape[0] - 1) * (i.shape[1] - 1) for i in graph.ids)
    return int(max(1, min(REFINE, np.floor(np.sqrt(MAX_REFINED / max(cells, 1))))))


def bilinear(grid: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The block's bilinear map X at lattice coordinates (u along i, v along j)."""
    nj, ni = grid.shape[:2]
    i0 = np.clip(np.floor(u).astype(int), 0, ni - 2)
    j0 = np.clip(np.floor(v).astype(int), 0, nj - 2)
    a, b = (u - i0)[..., None], (v - j0)[..., None]
    return (1 - b) * ((1 - a) * grid[j0, i0] + a * grid[j0, i0 + 1]) + b * (
        (1 - a) * grid[j0 + 1, i0] + a * grid[j0 + 1, i0 + 1]
    )


def _lattice_cells(rows: int, cols: int) -> np.ndarray:
    """The cells (m, 4) of a rows x cols lattice of flat node indices."""
    k = np.arange(rows * cols).reshape(rows, cols)
    return np.stack([k[:-1, :-1], k[:-1, 1:], k[1:, 1:], k[1:, :-1]], axis=-1).reshape(-1, 4)


def own_diffusion(grid: np.ndarray) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
    """Each cell's lattice factors (along i, along j), each (nj - 1, ni - 1), of the equation
    of xi and of that of eta.

    The variable-diffusion operator pulled back to the lattice of a cell of length L along i
    and thickness h along j is (1/M) diag(h / L, L / h) (the physical Laplacian in lattice
    coordinates): across a cell a hundred times thinner than long, nodes move together (a
    wall's rows slide along it as one; a trailing edge that stays holds the thin cells beside
    it), and the thin rows are where the flat ones do not move. Each coordinate's equation
    takes it times the unadapted grid's own density along that coordinate, c = a(j) L / h
    for xi and c = b(i) h / L for eta, which makes the tensor's entry along the coordinate a
    function of the other index only (a(j) for xi, b(i) for eta): then xi = u and eta = v
    solve the equations exactly with M constant, and the unadapted grid is kept where the
    field is flat (the physical solve's own control functions do the same). a and b are the
    geometric means of L / h's inverse along each row and of L / h along each column."""
    length = np.linalg.norm(np.diff(grid, axis=1), axis=-1)
    length = 0.5 * (length[1:] + length[:-1])  # (nj - 1, ni - 1)
    thick = np.linalg.norm(np.diff(grid, axis=0), axis=-1)
    thick = 0.5 * (thick[:, 1:] + thick[:, :-1])
    q = np.log(np.maximum(length, 1e-300) / np.maximum(thick, 1e-300))  # log(L / h)
    row = np.broadcast_to(-q.mean(axis=1, keepdims=True), q.shape)  # log a(j)
    col = np.broadcast_to(q.mean(axis=0, keepdims=True), q.shape)  # log b(i)
    return (np.exp(row), np.exp(row + 2 * q)), (np.exp(col - 2 * q), np.exp(col))


@dataclass
class _Block:
    """A block's refined lattice: its points in (u, v) and in the plane, |grad f|, the
    smoothed grad f grad f^T and |H| at its nodes, the nodes' areas (their cells' mean),
    the direction of its sub-cells' i lines (radians) and its sub-cells' lattice factors
    (:func:`own_diffusion`)."""

    grid: np.ndarray
    ids: np.ndarray
    u: np.ndarray
    v: np.ndarray
    points: np.ndarray
    gradient: np.ndarray
    tensor: np.ndarray
    hessian: np.ndarray
    area: np.ndarray
    heading: np.ndarray
    diffusion: tuple[tuple[np.ndarray, np.ndarray], ...]


@dataclass
class _Run:
    """A block side's nodes between two that stay (ids in run order), where it lies in a
    block ((block, side name, first and last lattice index along the side)), and the
    boundary piece it is (with ``reverse`` when the piece runs the other way), if any."""

    ids: np.ndarray
    block: int
    side: str
    first: int
    last: int
    piece: int | None
    reverse: bool


def _sides(ids: np.ndarray) -> dict[str, np.ndarray]:
    return {"bottom": ids[0, :], "top": ids[-1, :], "left": ids[:, 0], "right": ids[:, -1]}


class ParameterSpace:
    """The blocks of ``graph`` prepared for adapting to a field: refined lattices, the field
    sampled once on them, the sides cut into runs. :meth:`solve` adapts with a strength at
    each node (the guard lowers it round cells that break), capped where asked by the
    guard's ``limit`` (the largest MaxIncludedAngle allowed)."""

    def __init__(self, graph: NodeGraph, sample, limit: float = np.inf) -> None:
        self.graph, self.sample = graph, sample
        self.r = r = refinement(graph)
        self.pieces = pieces_of(graph)
        self.blocks = []
        for ids in graph.ids:
            grid = graph.points[ids]
            nj, ni = ids.shape
            v, u = np.meshgrid(np.arange((nj - 1) * r + 1) / r, np.arange((ni - 1) * r + 1) / r)
            u, v = u.T, v.T
            points = bilinear(grid, u, v)
            flat = points.reshape(-1, 2)
            cells = _lattice_cells(*u.shape)
            f, passes = sample(flat), SMOOTHING_PER_CELL * r
            g = gradient_size(flat, cells, f, passes).reshape(u.shape)
            tensor = gradient_tensor(flat, cells, f, passes).reshape(*u.shape, 3)
            hessian = hessian_tensor(flat, cells, f, passes).reshape(*u.shape, 3)
            area = to_nodes(cells, cell_areas(flat, cells), len(flat)).reshape(u.shape)
            along_i = np.diff(points, axis=1)
            along_i = along_i[1:] + along_i[:-1]
            heading = np.arctan2(along_i[..., 1], along_i[..., 0])
            diffusion = tuple(
                tuple(np.kron(factor, np.ones((r, r))) for factor in pair)
                for pair in own_diffusion(grid)
            )
            self.blocks.append(
                _Block(grid, ids, u, v, points, g, tensor, hessian, area, heading, diffusion)
            )
        self.limit = limit
        self.runs = self._runs()
        # the monitor's scale: the largest |grad f| the refined lattices see
        self.largest = max(float(b.gradient.max()) for b in self.blocks)
        # the curvature metric's: Huang's alpha over every block's area
        self.alpha = curvature_intensity(
            np.concatenate([b.hessian.reshape(-1, 3) for b in self.blocks]),
            np.concatenate([b.area.ravel() for b in self.blocks]),
        )
        self._shear: dict[bool, list[np.ndarray]] = {}
        refined = [b.points for b in self.blocks]
        self.joined = Joined(graph, refined, r) if len(self.blocks) > 1 else None

    def shear(self, curvature: bool = False) -> list[np.ndarray]:
        """Each block's shear cap at its refined nodes (:func:`shear_cap`, the guard's
        ``limit``) across the principal direction of grad f grad f^T or (``curvature``) of
        |H|: made at the first capped solve, as most grids never ask one."""
        if curvature not in self._shear:
            caps = []
            for block in self.blocks:
                across = principal_direction(block.hessian if curvature else block.tensor)
                caps.append(shear_cap(*_edges(block.points), across, self.limit))
            self._shear[curvature] = caps
        return self._shear[curvature]

    def _runs(self) -> list[_Run]:
        """Every block side's runs between the nodes that stay; each run once (a wake cut,
        a seam or an interface is two blocks' sides, or two sides of one)."""
        by_ids = {}
        for k, piece in enumerate(self.pieces):
            by_ids[tuple(piece.ids)] = (k, False)
            by_ids[tuple(piece.ids[::-1])] = (k, True)
        seen, runs = set(), []
        for b, block in enumerate(self.blocks):
            for name, side in _sides(block.ids).items():
                stops = np.flatnonzero(self.graph.held[side])
                stops = np.union1d(stops, [0, len(side) - 1])
                for first, last in zip(stops[:-1], stops[1:]):
                    ids = side[first : last + 1]
                    key = tuple(ids) if ids[0] <= ids[-1] else tuple(ids[::-1])
                    if last - first < 2 or key in seen:
                        continue
                    seen.add(key)
                    piece, reverse = by_ids.get(tuple(ids), (None, False))
                    runs.append(_Run(ids, b, name, int(first), int(last), piece, reverse))
        return runs

    @staticmethod
    def _side_values(side: str, values: np.ndarray) -> np.ndarray:
        """A refined lattice's ``values`` along a side."""
        return {
            "bottom": values[0, :],
            "top": values[-1, :],
            "left": values[:, 0],
            "right": values[:, -1],
        }[side]

    def solve(
        self,
        strength: np.ndarray,
        isotropic: bool = False,
        capped: bool = False,
        curvature: bool = False,
        joined: bool = False,
        slip: bool = False,
    ) -> Solved:
        """The grid adapted with the monitor of ``strength`` at each node, its diffusion
        tensor compressing across a front only or (``isotropic``) in every direction;
        ``capped``: with the shear cap of the guard's bound (:func:`shear_cap`);
        ``curvature``: the tensor of the interpolation error's curvature metric
        (:func:`curvature_diffusion`, intensity strength / (``CURVATURE_STRENGTH`` alpha))
        in place of the gradient's; ``joined``: a multi-block grid's blocks solved joined
        (:class:`Joined`: its junctions and interfaces move), else each in its own
        parameter space; ``slip`` (joined): solved again with the slip of that solve's
        compression (:func:`slipped`: grid lines turned along a front, not sheared)."""
        graph, largest = self.graph, self.largest
        tensors = []
        for k, block in enumerate(self.blocks):
            beta = bilinear(strength[block.ids][..., None], block.u, block.v)[..., 0]
            shear = self.shear(curvature)[k] if capped else None
            if curvature:
                intensity = beta / (CURVATURE_STRENGTH * self.alpha)
                tensors.append(curvature_diffusion(block.hessian, intensity, isotropic, shear))
            else:
                tensors.append(
                    diffusion_tensor(block.gradient, block.tensor, beta, largest, isotropic, shear)
                )
        points = graph.points.copy()
        params = [piece.s.copy() for piece in self.pieces]
        # each run's share of the way along it at its refined points, in run order: an
        # interface's, a cut's or a seam's from its one-dimensional equations (the same from
        # both sides), a boundary piece's from its block's solve (its natural condition);
        # joined blocks: a boundary piece's from the one-dimensional equations, interfaces
        # from the joined solve
        shares: dict[tuple, np.ndarray] = {}
        joined = joined and self.joined is not None
        for run in self.runs:
            if (run.piece is None) != joined:
                along = self._along(run, tensors[run.block])
                cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (along[1:] + along[:-1]))])
                self._place(run, cumulative / cumulative[-1], shares, points, params)
        if joined:
            self._joined(tensors, shares, points, slip)
        else:
            self._blocks(tensors, shares, points, params)
        return Solved(points, params, 1)

    def _joined(
        self,
        tensors: list[np.ndarray],
        shares: dict[tuple, np.ndarray],
        points: np.ndarray,
        slip: bool = False,
    ) -> None:
        """The joined blocks' inner nodes placed in ``points`` (:class:`Joined`), the
        boundary pieces' refined points held where their ``shares`` put them; ``slip``:
        solved again with each tensor slipped by the first solution's compression."""
        joined, r = self.joined, self.r
        xi = joined.points.copy()
        for run in self.runs:
            if run.piece is not None:
                n, line = len(run.ids) - 1, self.graph.points[run.ids]
                at = n * shares[tuple(run.ids)]
                k = np.clip(np.floor(at).astype(int), 0, n - 1)
                t = (at - k)[:, None]
                ids = self._side_values(run.side, joined.ids[run.block])
                xi[ids[run.first * r : run.last * r + 1]] = (1 - t) * line[k] + t * line[k + 1]
        given = xi.copy()
        lap, triangles = joined.system(tensors)
        solve_lattice(lap, xi, joined.fixed)
        if slip:
            jacobian = joined.jacobian(xi, triangles)
            tensors = [
                slipped(d, principal_direction(b.tensor), jacobian[ids], *_edges(b.points))
                for d, b, ids in zip(tensors, self.blocks, joined.ids)
            ]
            xi = given
            lap, triangles = joined.system(tensors)
            solve_lattice(lap, xi, joined.fixed)
        points[joined.inner] = joined.placed(xi, triangles, self.graph.points[joined.inner])

    def _blocks(
        self,
        tensors: list[np.ndarray],
        shares: dict[tuple, np.ndarray],
        points: np.ndarray,
        params: list[np.ndarray],
    ) -> None:
        """Each block solved in its own parameter space (:meth:`_interior`), its boundary
        pieces placed by their natural condition there."""
        r = self.r
        solved = [self._interior(b, d, shares, points) for b, d in zip(self.blocks, tensors)]
        for run in self.runs:
            if run.piece is not None:
                xi, eta = solved[run.block]
                values = xi if run.side in ("bottom", "top") else eta
                along = self._side_values(run.side, values)[run.first * r : run.last * r + 1]
                share = np.maximum.accumulate((along - run.first) / (run.last - run.first))
                self._place(run, np.clip(share, 0.0, 1.0), shares, points, params)

    def _along(self, run: _Run, tensor: np.ndarray) -> np.ndarray:
        """The monitor of a run's one-dimensional equations at its refined points: 1 / (s^T D
        s), the interior's diffusion along the run's own direction s inverted (M where the
        monitor is isotropic, 1 along a front)."""
        r, block = self.r, self.blocks[run.block]
        span = slice(run.first * r, run.last * r + 1)
        line = self._side_values(run.side, block.points)[span]
        d = self._side_values(run.side, tensor)[span]
        s = np.gradient(line, axis=0)
        s /= np.maximum(np.linalg.norm(s, axis=1, keepdims=True), 1e-300)
        along = d[:, 0] * s[:, 0] ** 2 + 2 * d[:, 1] * s[:, 0] * s[:, 1] + d[:, 2] * s[:, 1] ** 2
        return 1.0 / along

    def _place(
        self,
        run: _Run,
        share: np.ndarray,
        shares: dict[tuple, np.ndarray],
        points: np.ndarray,
        params: list[np.ndarray],
    ) -> None:
        """Place a run's inner nodes where its ``share`` (at its refined points, 0 to 1)
        passes theirs: on a boundary piece's curve, or on the run's own polyline."""
        shares[tuple(run.ids)] = share
        shares[tuple(run.ids[::-1])] = 1.0 - share[::-1]
        n, r = len(run.ids) - 1, self.r
        u = np.interp(np.arange(n + 1) / n, share, np.arange(n * r + 1) / r)  # run index
        inner = run.ids[1:-1]
        if run.piece is not None:
            piece = self.pieces[run.piece]
            at = n - u if run.reverse else u  # the piece's own index
            s = np.interp(at, np.arange(n + 1), piece.s)
            points[inner] = piece.curve(s[1:-1])
            params[run.piece][1:-1] = s[::-1][1:-1] if run.reverse else s[1:-1]
        else:
            line = self.graph.points[run.ids]
            k = np.clip(np.floor(u).astype(int), 0, n - 1)
            t = (u - k)[:, None]
            points[inner] = ((1 - t) * line[k] + t * line[k + 1])[1:-1]

    def _interior(
        self, block: _Block, d: np.ndarray, shares: dict[tuple, np.ndarray], points: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Solve the block's (xi, eta) on its refined lattice, place its inner nodes at
        X(s), s where (xi, eta) = (i, j), and return (xi, eta)."""
        r, held = self.r, self.graph.held[block.ids]
        nj, ni = block.ids.shape
        rows, cols = block.u.shape
        xi, eta = block.u.copy(), block.v.copy()  # the values on the sides and held nodes
        fixed_xi = np.zeros((rows, cols), dtype=bool)
        fixed_xi[[0, -1], :] = True
        fixed_xi[:, [0, -1]] = True
        fixed_eta = fixed_xi.copy()
        free_pieces = {tuple(run.ids) for run in self.runs if run.piece is not None}
        for name, side in _sides(block.ids).items():
            stops = np.union1d(np.flatnonzero(self.graph.held[side]), [0, len(side) - 1])
            values, fixed = (xi, fixed_xi) if name in ("bottom", "top") else (eta, fixed_eta)
            line = {"bottom": 0, "top": -1, "left": 0, "right": -1}[name]
            for first, last in zip(stops[:-1], stops[1:]):
                ids = side[first : last + 1]
                span = slice(first * r + 1, last * r)  # the refined points inside the run
                index = (line, span) if name in ("bottom", "top") else (span, line)
                if tuple(ids) in free_pieces or tuple(ids[::-1]) in free_pieces:
                    fixed[index] = False  # a boundary piece: its natural condition
                elif tuple(ids) in shares:
                    values[index] = first + (last - first) * shares[tuple(ids)][1:-1]
        # cells whose four corners stay (a wall's first row asked) stay, with their insides
        whole = held[:-1, :-1] & held[:-1, 1:] & held[1:, :-1] & held[1:, 1:]
        sub = np.kron(whole, np.ones((r, r), dtype=bool))
        for fixed in (fixed_xi, fixed_eta):
            for dj, di in ((0, 0), (0, 1), (1, 0), (1, 1)):
                fixed[dj : rows - 1 + dj, di : cols - 1 + di] |= sub
            fixed[::r, ::r] |= held
        d11, d12, d22 = _in_frame(d, block.heading)
        for values, fixed, (along_i, along_j) in zip(
            (xi, eta), (fixed_xi, fixed_eta), block.diffusion
        ):
            if fixed.all():
                continue
            lap = _stiffness(along_i * d11, np.sqrt(along_i * along_j) * d12, along_j * d22)
            solve_lattice(lap, values, fixed)
        inner = np.zeros((nj, ni), dtype=bool)
        inner[1:-1, 1:-1] = True
        inner &= ~held
        targets = np.argwhere(inner)  # (j, i)
        if len(targets):
            uv = _inverted(xi, eta, block.u, block.v, targets[:, 1], targets[:, 0])
            points[block.ids[inner]] = bilinear(block.grid, uv[:, 0], uv[:, 1])
        return xi, eta


def _edges(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A refined lattice's (rows, cols, 2) edges at its nodes, along i and along j."""
    return np.gradient(points, axis=1), np.gradient(points, axis=0)


def solve_lattice(lap: csr_matrix, values: np.ndarray, fixed: np.ndarray) -> None:
    """``values`` (a refined lattice's, rows x cols, or a joined grid's nodes' (n, 2)) at
    the nodes not ``fixed`` (``values``' shape, less a last axis of columns), in place: the
    discrete equations' solution, the unique minimiser of the energy values^T lap values
    with the fixed values held (lap symmetric, positive definite on the free nodes), by one
    sparse factorisation. ``benchmarks/adapt_network.py`` puts a network in its place."""
    free, known = np.flatnonzero(~fixed.ravel()), np.flatnonzero(fixed.ravel())
    flat = values.reshape(fixed.size, -1)  # a view: solved in place
    rhs = -lap[free][:, known] @ flat[known]
    # a symmetric matrix: its minimum-degree ordering fills less (1.6 times faster at 40 000
    # unknowns than the default column ordering)
    lu = splu(lap[free][:, free].tocsc(), permc_spec="MMD_AT_PLUS_A", options=SYMMETRIC)
    flat[free] = lu.solve(rhs)


def _inverted(
    xi: np.ndarray, eta: np.ndarray, u: np.ndarray, v: np.ndarray, ti: np.ndarray, tj: np.ndarray
) -> np.ndarray:
    """The lattice coordinates (u, v) (k, 2) where the piecewise-linear map (xi, eta) of the
    refined lattice (each sub-cell two triangles) takes the integer points (ti, tj)."""
    rows, cols = xi.shape
    k = np.arange(rows * cols).reshape(rows, cols)
    c00, c01, c11, c10 = k[:-1, :-1], k[:-1, 1:], k[1:, 1:], k[1:, :-1]
    tri = np.concatenate(
        [np.stack([c00, c01, c11], -1).reshape(-1, 3), np.stack([c00, c11, c10], -1).reshape(-1, 3)]
    )
    target = np.full((int(tj.max()) + 2, int(ti.max()) + 2), -1)
    target[tj, ti] = np.arange(len(ti))
    px, py = xi.ravel()[tri], eta.ravel()[tri]
    lo_x, hi_x = np.ceil(px.min(1) - INSIDE_TOL), np.floor(px.max(1) + INSIDE_TOL)
    lo_y, hi_y = np.ceil(py.min(1) - INSIDE_TOL), np.floor(py.max(1) + INSIDE_TOL)
    nx = np.maximum(hi_x - lo_x + 1, 0).astype(int)
    ny = np.maximum(hi_y - lo_y + 1, 0).astype(int)
    count = nx * ny
    owner = np.repeat(np.arange(len(tri)), count)
    local = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    qx = lo_x[owner] + local % nx[owner]
    qy = lo_y[owner] + local // nx[owner]
    ok = (qx >= 0) & (qy >= 0) & (qx < target.shape[1]) & (qy < target.shape[0])
    owner, qx, qy = owner[ok], qx[ok].astype(int), qy[ok].astype(int)
    which = target[qy, qx]
    keep = which >= 0
    owner, qx, qy, which = owner[keep], qx[keep], qy[keep], which[keep]
    x0, y0 = px[owner, 0], py[owner, 0]
    e1x, e1y = px[owner, 1] - x0, py[owner, 1] - y0
    e2x, e2y = px[owner, 2] - x0, py[owner, 2] - y0
    det = e1x * e2y - e1y * e2x
    det = np.where(np.abs(det) > 1e-300, det, 1e-300)
    dx, dy = qx - x0, qy - y0
    l1 = (dx * e2y - dy * e2x) / det
    l2 = (e1x * dy - e1y * dx) / det
    inside = (l1 >= -INSIDE_TOL) & (l2 >= -INSIDE_TOL) & (l1 + l2 <= 1 + INSIDE_TOL)
    owner, which, l1, l2 = owner[inside], which[inside], l1[inside], l2[inside]
    _, first = np.unique(which, return_index=True)
    out = np.column_stack([u.ravel(), v.ravel()])
    corners = tri[owner[first]]
    a, b = l1[first, None], l2[first, None]
    found = (1 - a - b) * out[corners[:, 0]] + a * out[corners[:, 1]] + b * out[corners[:, 2]]
    uv = np.column_stack([ti, tj]).astype(float)  # a point no triangle holds stays
    uv[which[first]] = found
    return uv


def _in_frame(d: np.ndarray, heading: np.ndarray) -> tuple[np.ndarray, ...]:
    """The sub-cells' diffusion tensors (the mean of their nodes' D) in the frame of their i
    line (its direction first, its normal second): (d11, d12, d22), each (rows - 1,
    cols - 1). With D = I it is the identity, whatever the cell's angles."""
    mean = 0.25 * (d[:-1, :-1] + d[:-1, 1:] + d[1:, :-1] + d[1:, 1:])
    cos, sin = np.cos(heading), np.sin(heading)
    xx, xy, yy = mean[..., 0], mean[..., 1], mean[..., 2]
    d11 = xx * cos**2 + 2 * xy * cos * sin + yy * sin**2
    d22 = xx * sin**2 - 2 * xy * cos * sin + yy * cos**2
    d12 = (yy - xx) * cos * sin + xy * (cos**2 - sin**2)
    return d11, d12, d22


def _stiffness(k11: np.ndarray, k12: np.ndarray, k22: np.ndarray) -> csr_matrix:
    """The piecewise-linear finite-element operator of div(K grad) on a lattice (rows, cols)
    whose sub-cells (rows - 1, cols - 1) have the tensors K, each sub-cell cut into two
    triangles along the diagonal K's cross term favours: the edges then have the weights
    (k11 - |k12|) / 2 (along i, from each side), (k22 - |k12|) / 2 (along j) and |k12|
    (the diagonal), non-negative once |k12| is cut to min(k11, k22), so the operator is an
    M-matrix (the discrete maximum principle, Tutte's positive weights)."""
    rows, cols = k11.shape[0] + 1, k11.shape[1] + 1
    k = np.arange(rows * cols).reshape(rows, cols)
    cross = np.sign(k12) * np.minimum(np.abs(k12), np.minimum(k11, k22))
    side_i, side_j = 0.5 * (k11 - np.abs(cross)), 0.5 * (k22 - np.abs(cross))
    rising = cross > 0  # the diagonal from the sub-cell's (j, i) corner to (j + 1, i + 1)
    a = [
        k[:-1, :-1],
        k[1:, :-1],
        k[:-1, :-1],
        k[:-1, 1:],
        np.where(rising, k[:-1, :-1], k[:-1, 1:]),
    ]
    b = [k[:-1, 1:], k[1:, 1:], k[1:, :-1], k[1:, 1:], np.where(rising, k[1:, 1:], k[1:, :-1])]
    w = [side_i, side_i, side_j, side_j, np.abs(cross)]
    a, b, w = (np.concatenate([x.ravel() for x in part]) for part in (a, b, w))
    n = rows * cols
    return coo_matrix(
        (np.concatenate([w, w, -w, -w]), (np.r_[a, b, a, b], np.r_[a, b, b, a])), shape=(n, n)
    ).tocsr()
