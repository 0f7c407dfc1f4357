"""Reads what `pitvol measure FILE --export DIR` wrote (docs/report.md)."""
import csv
import json
import os


class ExportError(Exception):
    """The export directory is missing a file or holds a malformed one."""


def _csv(path, required=True):
    if not os.path.exists(path):
        if required:
            raise ExportError(f"{path} is missing: is this a `pitvol measure --export` directory?")
        return None
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def _floats(rows, key):
    return [float(r[key]) for r in rows]


class Export:
    """One measurement's export: result, model, points, layers, coverage,
    wall grid and outlines (the last two only for method surface)."""

    def __init__(self, directory):
        self.dir = directory
        try:
            with open(os.path.join(directory, "result.json")) as f:
                self.result = json.load(f)
            with open(os.path.join(directory, "model.json")) as f:
                self.model = json.load(f)
        except FileNotFoundError as e:
            raise ExportError(f"{e.filename} is missing: is this a `pitvol measure --export` directory?")
        except json.JSONDecodeError as e:
            raise ExportError(f"malformed JSON in {directory}: {e}")
        pts = _csv(os.path.join(directory, "points.csv"), required=False) or []
        self.x = _floats(pts, "x_mm")
        self.y = _floats(pts, "y_mm")
        self.z = _floats(pts, "z_mm")
        self.layers = _csv(os.path.join(directory, "layers.csv"))
        self.coverage = _csv(os.path.join(directory, "coverage.csv"))
        self.wall = _csv(os.path.join(directory, "wall_grid.csv"), required=False)
        self.outline = _csv(os.path.join(directory, "outline.csv"), required=False)

    @property
    def measured(self):
        return self.result.get("status") == "PV_OK"

    @property
    def rim_mm(self):
        r = self.model.get("rim_mm")
        return r if r is not None and r > 0 else None

    def outline_heights(self):
        """The heights of outline.csv, in file order."""
        seen = []
        for r in self.outline or []:
            h = float(r["height_mm"])
            if h not in seen:
                seen.append(h)
        return seen
