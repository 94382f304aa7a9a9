"""The figures: loss curves (Fig. 4), grids (Figs. 5, 7), angle histograms (Figs. 6, 8) and the
architecture study (Fig. 9). Plots use matplotlib (Agg); grid pictures are rendered off-screen
with pyvista, every panel with the same colour scale, and laid out side by side."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import Normalize  # noqa: E402

from .runs import LABELS, Budget  # noqa: E402

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

CLIM = (90.0, 180.0)  # MaxIncludedAngle colour scale of every grid picture (degrees)
OVER_COLOR = "magenta"  # cells above 180 degrees: folded
CMAP = "viridis"
COLORS = {"pinn": "tab:blue", "mgnet": "tab:red", "tfi": "tab:gray", "elliptic": "tab:green"}
TERM_TITLES = {
    "eqns": "Loss_eqns (Laplace residual)",
    "bcs_bottom": "Loss_bcs bottom",
    "bcs_right": "Loss_bcs right",
    "bcs_top": "Loss_bcs top (paper: 'up')",
    "bcs_left": "Loss_bcs left",
    "data": "Loss_data (auxiliary lines)",
    "total": "Total loss (as minimised)",
    "lambda1": "lambda1 (dynamic weight)",
}
LOSS_TERMS = tuple(TERM_TITLES)


def _save(fig, path: Path, dpi: int = 110) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    return path


def _smooth(values: np.ndarray, window: int) -> np.ndarray:
    if window <= 1 or len(values) < window:
        return values
    kernel = np.ones(window) / window
    padded = np.concatenate([np.full(window - 1, values[0]), values])
    return np.convolve(padded, kernel, mode="valid")


def loss_figure(runs: dict[str, dict], path: Path, title: str, dpi: int = 110) -> Path:
    """Each loss term against step for the runs (method -> run), Adam and L-BFGS phases marked.

    A term that is identically zero in every run (the boundary terms under a hard boundary, the
    data term of MGNet) is left out for that run, or entirely.
    """
    terms = [
        t
        for t in LOSS_TERMS
        if any(np.any(np.asarray(r["history"].get(t, [0.0])) != 0) for r in runs.values())
    ]
    cols = min(4, len(terms))
    rows = -(-len(terms) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.2 * rows), squeeze=False)
    for ax, term in zip(axes.flat, terms):
        for method, run in runs.items():
            values = np.asarray(run["history"].get(term, []), dtype=float)
            if values.size == 0 or not np.any(values != 0):
                continue
            n_adam = int(run["n_adam"])
            steps = np.arange(1, len(values) + 1)
            color = COLORS.get(method, "black")
            ax.plot(steps[:n_adam], values[:n_adam], color=color, alpha=0.25, lw=0.5)
            window = max(1, n_adam // 100)
            ax.plot(
                steps[:n_adam],
                _smooth(values[:n_adam], window),
                color=color,
                lw=1.2,
                label=f"{LABELS[method]}: {values[-1]:.3e}",
            )
            ax.plot(steps[n_adam:], values[n_adam:], color=color, lw=1.2)
        n_adam = max(int(r["n_adam"]) for r in runs.values())
        ax.axvline(n_adam + 0.5, color="black", ls="--", lw=0.8)
        ax.axvspan(n_adam + 0.5, ax.get_xlim()[1], color="0.92", zorder=0)
        if term != "lambda1":
            ax.set_yscale("log")
        ax.set_title(TERM_TITLES[term], fontsize=9)
        ax.set_xlabel("Adam epoch, then L-BFGS evaluation (shaded)", fontsize=7)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=7, title="final value", title_fontsize=7)
    for ax in list(axes.flat)[len(terms) :]:
        ax.axis("off")
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    return _save(fig, path, dpi)


def _crop(image: np.ndarray, pad: int = 6) -> np.ndarray:
    """Trim the white margin of a rendered picture."""
    ink = np.any(image[..., :3] < 250, axis=-1)
    rows, cols = np.flatnonzero(ink.any(axis=1)), np.flatnonzero(ink.any(axis=0))
    if rows.size == 0:
        return image
    r0, r1 = max(rows[0] - pad, 0), min(rows[-1] + pad + 1, image.shape[0])
    c0, c1 = max(cols[0] - pad, 0), min(cols[-1] + pad + 1, image.shape[1])
    return image[r0:r1, c0:c1]


class GridRenderer:
    """Off-screen pyvista pictures of grids coloured by MaxIncludedAngle, one reused window."""

    def __init__(self, width: int = 1000, clim: tuple[float, float] = CLIM) -> None:
        import pyvista as pv

        pv.OFF_SCREEN = True
        self.pv, self.width, self.clim = pv, width, clim
        self.plotter = pv.Plotter(off_screen=True, window_size=[width, width // 2])

    def image(self, run: dict) -> np.ndarray:
        """An RGB picture of the run's grid, boundary (red) and auxiliary lines (orange)."""
        from pinn_engine.io.vtkgrid import structured_grid

        pv, plotter = self.pv, self.plotter
        points = np.asarray(run["points"])
        lo, hi = points.reshape(-1, 2).min(axis=0), points.reshape(-1, 2).max(axis=0)
        aspect = float((hi[1] - lo[1]) / max(hi[0] - lo[0], 1e-12))
        plotter.clear()
        plotter.window_size = [self.width, int(np.clip(self.width * aspect, 100, 2 * self.width))]
        plotter.set_background("white")
        plotter.add_mesh(
            pv.wrap(structured_grid(points)),
            scalars="MaxIncludedAngle",
            preference="cell",
            show_edges=True,
            edge_color="black",
            line_width=0.5,
            cmap=CMAP,
            clim=self.clim,
            above_color=OVER_COLOR,
            show_scalar_bar=False,
        )
        ring = np.asarray(run["boundary_ring"])
        ring = np.vstack([ring, ring[:1]])
        plotter.add_mesh(
            pv.lines_from_points(np.column_stack([ring, np.zeros(len(ring))])),
            color="red",
            line_width=2,
        )
        for line in run.get("aux_lines", []):
            line = np.asarray(line)
            plotter.add_mesh(
                pv.lines_from_points(np.column_stack([line, np.zeros(len(line))])),
                color="orange",
                line_width=3,
            )
        plotter.view_xy()
        plotter.enable_parallel_projection()
        plotter.reset_camera()
        plotter.camera.tight(padding=0.03)
        return _crop(np.asarray(plotter.screenshot(None, return_img=True)))

    def close(self) -> None:
        self.plotter.close()


def make_renderer(width: int = 1000) -> GridRenderer | None:
    """A renderer, or None where no off-screen OpenGL is available (matplotlib draws then)."""
    try:
        return GridRenderer(width)
    except Exception:  # noqa: BLE001 - any failure to open a window means: fall back
        return None


def _draw_grid_matplotlib(ax, run: dict, clim: tuple[float, float]) -> None:
    """Fallback when no off-screen OpenGL is available: the same picture with matplotlib."""
    from matplotlib.collections import PolyCollection

    p = np.asarray(run["points"])
    quads = np.stack([p[:-1, :-1], p[:-1, 1:], p[1:, 1:], p[1:, :-1]], axis=2).reshape(-1, 4, 2)
    cmap = plt.get_cmap(CMAP).with_extremes(over=OVER_COLOR)
    coll = PolyCollection(
        quads,
        array=np.asarray(run["max_angle"]).ravel(),
        cmap=cmap,
        norm=Normalize(*clim),
        edgecolors="black",
        linewidths=0.2,
    )
    ax.add_collection(coll)
    ring = np.asarray(run["boundary_ring"])
    ax.plot(*np.vstack([ring, ring[:1]]).T, color="red", lw=1)
    for line in run.get("aux_lines", []):
        ax.plot(*np.asarray(line).T, color="orange", lw=1.5)
    ax.set_aspect("equal")
    ax.autoscale_view()


def mesh_figure(
    runs: Sequence[tuple[str, dict]],
    path: Path,
    title: str,
    renderer: GridRenderer | None = None,
    columns: int | None = None,
    dpi: int = 110,
) -> str:
    """Grids side by side, each coloured by MaxIncludedAngle on the same scale (``CLIM``).

    ``runs`` are (method, run) pairs. Returns what drew them: "pyvista" or "matplotlib".
    """
    clim = renderer.clim if renderer is not None else CLIM
    used, images = "matplotlib", []
    if renderer is not None:
        try:
            images = [renderer.image(run) for _, run in runs]
            used = "pyvista"
        except Exception:  # noqa: BLE001 - rendering failed: draw with matplotlib instead
            images = []
    n = len(runs)
    cols = columns or n
    rows = -(-n // cols)
    if images:
        ratio = max(im.shape[0] / im.shape[1] for im in images)
    else:
        pts = np.asarray(runs[0][1]["points"]).reshape(-1, 2)
        span = pts.max(axis=0) - pts.min(axis=0)
        ratio = float(span[1] / max(span[0], 1e-12))
    panel_w = 4.6
    fig, axes = plt.subplots(
        rows,
        cols,
        figsize=(panel_w * cols + 1.0, panel_w * ratio * rows + 0.9 * rows),
        squeeze=False,
    )
    for k, (ax, (method, run)) in enumerate(zip(axes.flat, runs)):
        if images:
            ax.imshow(images[k])
            ax.set_xticks([])
            ax.set_yticks([])
            for spine in ax.spines.values():
                spine.set_visible(False)
        else:
            _draw_grid_matplotlib(ax, run, clim)
            ax.axis("off")
        q = run["quality"]
        ax.set_title(
            f"({chr(97 + k)}) {LABELS[method]}\nmean {q['mean_max_angle']:.1f}°, "
            f"worst {q['worst_max_angle']:.1f}°, folded {q['folded_cells']}",
            fontsize=9,
        )
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    cmap = plt.get_cmap(CMAP).with_extremes(over=OVER_COLOR)
    mappable = plt.cm.ScalarMappable(norm=Normalize(*clim), cmap=cmap)
    bar = fig.colorbar(mappable, ax=list(axes.flat), fraction=0.025, pad=0.02, extend="max")
    bar.set_label("MaxIncludedAngle (deg); magenta: above 180 (folded)", fontsize=8)
    fig.suptitle(title, fontsize=11)
    _save(fig, path, dpi)
    return used


def angle_histograms(
    runs: Sequence[tuple[str, dict]], path: Path, title: str, dpi: int = 110
) -> Path:
    """Distribution of MaxIncludedAngle per method, same bins, with mean and worst marked."""
    angles = [np.asarray(run["max_angle"]).ravel() for _, run in runs]
    top = max(180.0, max(float(a.max()) for a in angles))
    bins = np.arange(90.0, top + 2.0, 2.0)
    fig, axes = plt.subplots(
        1, len(runs), figsize=(3.6 * len(runs), 3.2), sharex=True, sharey=True, squeeze=False
    )
    for ax, (method, _run), a in zip(axes.flat, runs, angles):
        color = COLORS.get(method, "black")
        ax.hist(np.clip(a, 90.0, None), bins=bins, color=color, alpha=0.75)
        mean, worst = float(a.mean()), float(a.max())
        ax.axvline(mean, color="black", ls="--", lw=1, label=f"mean {mean:.1f}°")
        ax.axvline(worst, color="black", ls=":", lw=1.2, label=f"worst {worst:.1f}°")
        ax.set_title(LABELS[method], fontsize=9)
        ax.set_xlabel("MaxIncludedAngle (deg)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=7)
    axes.flat[0].set_ylabel("cells", fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return _save(fig, path, dpi)


def architecture_figure(sweeps: dict[str, dict], path: Path, title: str, dpi: int = 110) -> Path:
    """Final loss against hidden layers and neurons per layer: every seed, mean and range.

    ``sweeps``: name -> {"x": [...], "label": str, "losses": [[seed values] per x]}.
    """
    fig, axes = plt.subplots(1, len(sweeps), figsize=(5.0 * len(sweeps), 3.8), squeeze=False)
    for ax, (name, sweep) in zip(axes.flat, sweeps.items()):
        xs = np.asarray(sweep["x"], dtype=float)
        means, lows, highs = [], [], []
        for x, values in zip(xs, sweep["losses"]):
            v = np.asarray([u for u in values if np.isfinite(u)], dtype=float)
            if v.size:
                ax.scatter(np.full(v.size, x), v, s=14, color="tab:blue", alpha=0.6, zorder=3)
                means.append(v.mean())
                lows.append(v.min())
                highs.append(v.max())
            else:
                means.append(np.nan)
                lows.append(np.nan)
                highs.append(np.nan)
                ax.text(
                    x,
                    0.03,
                    "failed",
                    transform=ax.get_xaxis_transform(),
                    ha="center",
                    fontsize=8,
                    color="tab:red",
                )
        ax.fill_between(xs, lows, highs, color="tab:blue", alpha=0.15, label="seed range")
        ax.plot(xs, means, color="tab:blue", marker="o", lw=1.5, label="mean over seeds")
        ax.set_yscale("log")
        ax.set_xticks(xs)
        ax.set_xlabel(sweep["label"], fontsize=9)
        ax.set_ylabel("final total loss", fontsize=9)
        ax.set_title(name, fontsize=10)
        ax.legend(fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return _save(fig, path, dpi)


N_FIGURES = 15


def make_figures(
    results: dict,
    budget: Budget,
    out: Path,
    step: Callable[[str], None] = lambda label: None,
) -> tuple[dict[str, Path], set[str]]:
    """Every figure of the report, and the per-cell angle CSVs of the pictured grids.

    Returns the figures by name and what drew the grids; ``step(label)`` follows progress.
    """
    from . import report
    from .analysis import pictured, select, sweep_data
    from .runs import FOUR_METHOD_CASES, LOSS_CASE, METHODS, PRESETS

    out = Path(out)
    figs: dict[str, Path] = {}
    renderers: set[str] = set()
    quick = budget.mode != "full"
    dpi = 70 if quick else 110
    renderer = make_renderer(400 if quick else 1000)

    def compare_set(case: str, preset: str, methods) -> list[tuple[str, dict]]:
        chosen = []
        for m in methods:
            run = pictured(select(results, "compare", case, preset, m))
            if run is not None:
                chosen.append((m, run))
        return chosen

    def grids_and_angles(
        runs, case: str, preset: str, names: tuple[str, str], key: str, **layout
    ) -> None:
        """The grids side by side (Fig. 5 or 7) and their angle histograms (Fig. 6 or 8)."""
        mesh, angles = names
        path = out / f"{mesh}_mesh_{case}_{preset}.png"
        renderers.add(
            mesh_figure(runs, path, f"{case} case, {preset} preset", renderer, dpi=dpi, **layout)
        )
        figs[f"{mesh}_{key}"] = path
        step(mesh)
        figs[f"{angles}_{key}"] = angle_histograms(
            runs,
            out / f"{angles}_angles_{case}_{preset}.png",
            f"MaxIncludedAngle per cell, {case} case, {preset} preset",
            dpi,
        )
        step(angles)

    for preset in PRESETS:
        neural = compare_set(LOSS_CASE, preset, ("pinn", "mgnet"))
        if neural:
            figs[f"fig4_{preset}"] = loss_figure(
                dict(neural),
                out / f"fig4_loss_{LOSS_CASE}_{preset}.png",
                f"Loss terms on the {LOSS_CASE} case, {preset} preset (seed 0)",
                dpi,
            )
            step("fig4")
            grids_and_angles(neural, LOSS_CASE, preset, ("fig5", "fig6"), preset)
        every = compare_set(LOSS_CASE, preset, METHODS)
        if every:
            report.write_angles_csv(every, out / f"angles_{LOSS_CASE}_{preset}.csv")
    order = ("tfi", "elliptic", "mgnet", "pinn")  # the paper's Fig. 7 order
    for case in FOUR_METHOD_CASES:
        for preset in PRESETS:
            chosen = compare_set(case, preset, order)
            if not chosen:
                continue
            grids_and_angles(chosen, case, preset, ("fig7", "fig8"), f"{case}_{preset}", columns=2)
            report.write_angles_csv(chosen, out / f"angles_{case}_{preset}.csv")
    sweeps = sweep_data(results, budget)
    figs["fig9"] = architecture_figure(
        {k: v for k, v in sweeps.items() if not k.startswith("_")},
        out / "fig9_architecture.png",
        f"Proposed method, {budget.sweep_case} case, {budget.sweep_preset} preset: final loss "
        f"after {budget.sweep_adam_epochs} Adam epochs + {budget.sweep_lbfgs_iterations} "
        f"L-BFGS iterations, {len(budget.sweep_seeds)} seeds",
        dpi,
    )
    step("fig9")
    if renderer is not None:
        renderer.close()

    return figs, renderers
