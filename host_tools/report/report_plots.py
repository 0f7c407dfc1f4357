"""The scan report's figures (docs/report.md explains each one).

Each function takes an Export (report_data.py) and returns a matplotlib
Figure, or None when the export has nothing to draw it from."""
import matplotlib

matplotlib.use("Agg")  # files only: no display on a field laptop's CI
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

# Wall bin states of wall_grid.csv, in colour-map order.
STATES = ["none", "seen", "floor", "short_bridge", "unseen"]
STATE_COLOURS = ["#bdbdbd", "#2e7d32", "#c8b273", "#81c784", "#e65100"]
STATE_LABELS = ["no value", "seen", "floor points", "short bridge (counts as seen)",
                "unseen (bridged)"]


def _runs(flags):
    """(start, end) index ranges of consecutive true flags."""
    runs, start = [], None
    for i, f in enumerate(flags + [False]):
        if f and start is None:
            start = i
        elif not f and start is not None:
            runs.append((start, i - 1))
            start = None
    return runs


def area_profile(ex):
    """Section area against height: kept and rejected layers, bridged bands."""
    if not ex.layers:
        return None
    z = np.array([float(r["z_mm"]) for r in ex.layers])
    a = np.array([float(r["area_mm2"]) for r in ex.layers]) / 100.0  # cm2
    kept = np.array([r["kept"] == "1" for r in ex.layers])
    bridged = [r["bridged"] == "1" for r in ex.layers]
    fig, ax = plt.subplots(figsize=(9, 4.2))
    half = 0.5 * (z[1] - z[0]) if len(z) > 1 else 0.25
    for i, (s, e) in enumerate(_runs(bridged)):
        ax.axvspan(z[s] - half, z[e] + half, color="#ffb74d", alpha=0.35, lw=0,
                   label="bridged band (wall not seen)" if i == 0 else None)
    ok = np.isfinite(a)
    ax.plot(z[kept & ok], a[kept & ok], ".", ms=2.5, color="#1565c0", label="kept layer")
    if (~kept & ok).any():
        ax.plot(z[~kept & ok], a[~kept & ok], "x", ms=4, color="#c62828",
                label="rejected layer" if ex.model.get("wall_grid") is None
                else "layer mostly unseen")
    unseen = [r.get("unseen_share") for r in ex.layers]
    if all(u not in (None, "") for u in unseen):  # surface: the share of each layer's wall not seen
        share = np.array([float(u) for u in unseen])
        ax2 = ax.twinx()
        ax2.fill_between(z, 0, 100 * share, color="#e65100", alpha=0.25, lw=0)
        ax2.set_ylim(0, 100)
        ax2.set_ylabel("wall not seen at that height (%)", color="#e65100")
        ax2.tick_params(axis="y", colors="#e65100")
        ax.set_zorder(ax2.get_zorder() + 1)  # the area curve over the shading
        ax.patch.set_visible(False)
    if ex.rim_mm:
        ax.axvline(ex.rim_mm, color="k", lw=1, ls="--", label=f"rim {ex.rim_mm:.1f} mm")
    ax.axvline(0.0, color="#6d4c41", lw=1, label="floor plane")
    ax.set_xlabel("height above the floor plane (mm)")
    ax.set_ylabel("section area (cm²)")
    ax.set_ylim(0, (np.nanmax(a[ok]) if ok.any() else 1.0) * 1.08)
    ax.set_title("Area against height, per 0.5 mm layer")
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    return fig


def _points_near(ex, h, band):
    z = np.asarray(ex.z)
    sel = np.abs(z - h) <= band
    return np.asarray(ex.x)[sel], np.asarray(ex.y)[sel]


def outlines(ex):
    """The fitted outline at several heights over the points of that height."""
    heights = ex.outline_heights()
    if not heights:
        return None
    rows = ex.outline
    n = len(heights)
    fig, axes = plt.subplots(1, n, figsize=(3.0 * n, 3.4))
    axes = np.atleast_1d(axes)
    band = ex.model["wall_grid"]["dz_mm"] if ex.model.get("wall_grid") else 1.0
    for ax, h in zip(axes, heights):
        sel = [r for r in rows if float(r["height_mm"]) == h]
        ox = np.array([float(r["x_mm"]) for r in sel])
        oy = np.array([float(r["y_mm"]) for r in sel])
        unseen = np.array([r["state"] in ("unseen", "none") for r in sel])
        px, py = _points_near(ex, h, band)
        ax.plot(px, py, ".", ms=3.0, color="#9e9e9e", label=f"points ±{band:g} mm",
                rasterized=True, zorder=1)
        ax.plot(ox, oy, "-", lw=0.9, color="#1565c0", label="fitted wall", zorder=3)
        if unseen.any():
            m = np.where(unseen, oy, np.nan)
            ax.plot(ox, m, "-", lw=2.6, color="#e65100", label="bridged (unseen)", zorder=2)
        pad = 25.0
        ax.set_xlim(ox.min() - pad, ox.max() + pad)
        ax.set_ylim(oy.min() - pad, oy.max() + pad)
        ax.set_aspect("equal")
        ax.set_title(f"z = {h:.0f} mm", fontsize=10)
        ax.tick_params(labelsize=7)
    axes[0].legend(loc="upper left", fontsize=6, markerscale=3)
    fig.suptitle("Outline (wall radius around the axis) at several heights, levelled frame, mm")
    fig.tight_layout()
    return fig


def coverage_map(ex):
    """Angle around the axis against height: seen and unseen wall."""
    bands = ex.coverage or []
    has_grid = bool(ex.wall)
    fig, axes = plt.subplots(1, 2 if has_grid else 1, figsize=(9, 4.2), squeeze=False,
                             gridspec_kw={"width_ratios": [4, 1]} if has_grid else None)
    axes = axes[0]
    if has_grid:
        g = ex.model["wall_grid"]
        T, Z = g["theta_bins"], g["z_bins"]
        idx = {s: i for i, s in enumerate(STATES)}
        img = np.array([idx.get(r["state"], 0) for r in ex.wall]).reshape(Z, T)
        z0, dz = g["z0_mm"], g["dz_mm"]
        ax = axes[0]
        ax.imshow(img, origin="lower", aspect="auto", interpolation="nearest",
                  cmap=ListedColormap(STATE_COLOURS), vmin=-0.5, vmax=len(STATES) - 0.5,
                  extent=(0, 360, z0, z0 + Z * dz))
        ax.set_xlabel("angle around the pit's axis (deg, from levelled +x)")
        ax.set_ylabel("height (mm)")
        ax.set_xticks(range(0, 361, 45))
        ax.set_ylim(max(z0, -5.0), z0 + Z * dz)
        ax.set_title("Wall seen by the scan (surface model bins)")
        present = sorted(set(img.ravel().tolist()))
        ax.legend(handles=[Patch(color=STATE_COLOURS[i], label=STATE_LABELS[i]) for i in present],
                  loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=3, fontsize=7)
    ax = axes[-1]
    if bands:
        lo = [float(b["z_from_mm"]) for b in bands]
        hi = [float(b["z_to_mm"]) for b in bands]
        s = [100.0 * float(b["seen_share"]) for b in bands]
        ax.barh(lo, s, height=[h - l for l, h in zip(lo, hi)], align="edge",
                color=["#2e7d32" if v >= 50 else "#e65100" for v in s], edgecolor="white")
        ax.set_xlim(0, 100)
        ax.set_ylim(lo[0], hi[-1])
    ax.set_xlabel("seen (%)")
    ax.set_title("Per band", fontsize=10)
    if not has_grid:
        ax.set_ylabel("height (mm)")
    fig.tight_layout()
    return fig


def side_view(ex):
    """The levelled cloud from the side, with the floor plane and the rim."""
    if not ex.x:
        return None
    x, y, z = np.asarray(ex.x), np.asarray(ex.y), np.asarray(ex.z)
    g = ex.model.get("wall_grid")
    cx = g["axis_x_mm"] if g else float(np.median(x))
    cy = g["axis_y_mm"] if g else float(np.median(y))
    rim = ex.rim_mm
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.4), sharey=True)
    # Around the pit: the strays far away would shrink it to a dot.
    zlo, zhi = np.percentile(z, [0.5, 99.5])
    span = np.percentile(np.hypot(x - cx, y - cy), 99.0) * 1.05
    for ax, u, c, name in ((axes[0], x, cx, "x"), (axes[1], y, cy, "y")):
        ax.plot(u - c, z, ",", color="#616161", alpha=0.6, rasterized=True)
        ax.axhline(0.0, color="#6d4c41", lw=1.5, label="floor plane (z = 0)")
        if rim:
            ax.axhline(rim, color="#1565c0", lw=1.5, ls="--", label=f"rim ({rim:.1f} mm)")
        if ex.wall:
            _section(ax, ex, 0.0 if name == "x" else 90.0)
        ax.set_xlim(-span, span)
        ax.set_ylim(min(zlo, 0.0) - 10, max(zhi, rim or 0.0) + 10)
        ax.set_xlabel(f"levelled {name} from the axis (mm)")
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("height above the floor plane (mm)")
    axes[0].legend(loc="lower left", fontsize=7)
    fig.suptitle("Side view of the levelled cloud (every exported point)")
    fig.tight_layout()
    return fig


def _section(ax, ex, angle_deg):
    """The model's wall in the vertical plane through the axis at angle_deg
    (and the opposite side), drawn over the side view."""
    g = ex.model["wall_grid"]
    T = g["theta_bins"]
    t0 = int(round(angle_deg / 360.0 * T - 0.5)) % T
    t1 = (t0 + T // 2) % T
    # The axis leans: the wall is drawn where it is, relative to the
    # axis at z = 0 as the points are.
    lean = g["axis_dx"] if angle_deg == 0.0 else g["axis_dy"]
    zs, r0, r1 = [], [], []
    for k in range(g["z_bins"]):
        a, b = ex.wall[k * T + t0], ex.wall[k * T + t1]
        zk = float(a["z_mm"])
        if zk < 0 or (ex.rim_mm and zk > ex.rim_mm):
            continue
        zs.append(zk)
        r0.append(lean * zk + float(a["radius_mm"]))
        r1.append(lean * zk - float(b["radius_mm"]))
    ax.plot(r0, zs, "-", color="#e65100", lw=1.2, label="fitted wall")
    ax.plot(r1, zs, "-", color="#e65100", lw=1.2)


def surface_3d(ex):
    """The reconstructed pit in 3D: the surface model's wall (seen wall
    blue, wall bridged over a gap orange, floor-bounded bins brown) over a
    floor disc at z = 0; the per-layer methods' kept layer outlines are
    not a surface, so their page shows the levelled points instead."""
    from mpl_toolkits.mplot3d import Axes3D  # noqa: F401  (registers the projection)
    fig = plt.figure(figsize=(7.0, 5.6))
    ax = fig.add_subplot(projection="3d")
    if ex.wall:
        g = ex.model["wall_grid"]
        T, Z = g["theta_bins"], g["z_bins"]
        x = np.array([float(r["x_mm"]) for r in ex.wall]).reshape(Z, T)
        y = np.array([float(r["y_mm"]) for r in ex.wall]).reshape(Z, T)
        z = np.array([float(r["z_mm"]) for r in ex.wall]).reshape(Z, T)
        state = np.array([r["state"] for r in ex.wall]).reshape(Z, T)
        rim = ex.rim_mm or float(z.max())
        keep = (z[:, 0] >= 0.0) & (z[:, 0] <= rim)  # floor plane to rim, as the volume
        x, y, z, state = x[keep], y[keep], z[keep], state[keep]
        # Closed around: the first column again.
        x, y, z = (np.hstack([a, a[:, :1]]) for a in (x, y, z))
        state = np.hstack([state, state[:, :1]])
        colours = {"seen": "#90caf9", "short_bridge": "#90caf9", "floor": "#a1887f",
                   "unseen": "#ff9800", "none": "#bdbdbd"}
        face = np.empty(state.shape + (4,))
        for k in range(state.shape[0]):
            for t in range(state.shape[1]):
                face[k, t] = matplotlib.colors.to_rgba(colours.get(state[k, t], "#bdbdbd"))
        ax.plot_surface(x, y, z, facecolors=face, rstride=1, cstride=1, linewidth=0,
                        antialiased=False, shade=True)
        # The floor: the wall's lowest ring filled at z = 0.
        ring_x, ring_y = x[0], y[0]
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection
        ax.add_collection3d(Poly3DCollection([list(zip(ring_x, ring_y, np.zeros_like(ring_x)))],
                                             facecolor="#8d6e63", alpha=0.6))
        handles = [Patch(color="#90caf9", label="wall seen"),
                   Patch(color="#ff9800", label="wall not seen, bridged (in the interval)"),
                   Patch(color="#8d6e63", label="floor (z = 0)")]
        span = max(np.ptp(x), np.ptp(y))
        cx, cy = float(np.mean(x)), float(np.mean(y))
        ax.set_xlim(cx - span / 2, cx + span / 2)
        ax.set_ylim(cy - span / 2, cy + span / 2)
        ax.set_zlim(0, max(rim, span * 0.3))
        ax.set_title("The pit as measured: the surface model's wall and floor")
    elif ex.x:
        x, y, z = np.asarray(ex.x), np.asarray(ex.y), np.asarray(ex.z)
        rim = ex.rim_mm
        inside = (z >= 0) & (z <= (rim if rim else np.inf))
        ax.scatter(x[inside], y[inside], z[inside], s=0.3, c=z[inside], cmap="viridis", rasterized=True)
        handles = []
        ax.set_title("The levelled points from the floor plane to the rim (no surface model: "
                     "per-layer method)", fontsize=9)
    else:
        plt.close(fig)
        return None
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_zlabel("height (mm)")
    ax.view_init(elev=28, azim=-60)
    if handles:
        ax.legend(handles=handles, loc="upper left", fontsize=7)
    fig.tight_layout()
    return fig


def all_figures(ex):
    """(id, title, figure) in page order; figure None when not available."""
    return [
        ("pit3d", "The pit in 3D", surface_3d(ex)),
        ("area", "Area against height", area_profile(ex)),
        ("outline", "Outline at several heights", outlines(ex)),
        ("coverage", "Coverage map", coverage_map(ex)),
        ("side", "Side view", side_view(ex)),
    ]


def close(figs):
    for _, _, f in figs:
        if f is not None:
            plt.close(f)

