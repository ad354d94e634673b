"""Small geometry helpers of check_step.py, in plain Python (the environment has no numpy):
distances, angles, JSON-safe numbers and two spatial grids for nearest-point queries."""

import math

# A face whose bounding box spans more grid cells than this is checked for every query instead.
MAX_CELLS_PER_FACE = 4096

def distance(a, b):
    return math.sqrt((a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2 + (a[2] - b[2]) ** 2)


def angle_deg(n1, n2):
    """Angle between two unit vectors, in degrees."""
    dot = n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2]
    return math.degrees(math.acos(max(-1.0, min(1.0, dot))))


def json_safe(value):
    """The value with every NaN or infinite float replaced by None: JSON has no such numbers."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {key: json_safe(item) for key, item in value.items()}
    if isinstance(value, list):
        return [json_safe(item) for item in value]
    return value


def max_or_none(current, value):
    if value is None:
        return current
    if current is None or value > current:
        return value
    return current


class PointGrid:
    """Points in a dict of cubic cells, to find those within a radius no larger than the cell."""

    def __init__(self, cell):
        self.cell = cell
        self.cells = {}

    def key(self, p):
        return (math.floor(p[0] / self.cell), math.floor(p[1] / self.cell),
                math.floor(p[2] / self.cell))

    def add(self, index, p):
        self.cells.setdefault(self.key(p), []).append((index, p))

    def within(self, p, radius):
        """Indices of the points within radius (at most one cell) of p."""
        kx, ky, kz = self.key(p)
        found = []
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for index, q in self.cells.get((kx + dx, ky + dy, kz + dz), ()):
                        if distance(p, q) <= radius:
                            found.append(index)
        return found


class BoxGrid:
    """Axis-aligned boxes registered in every cubic cell they overlap, to find those holding a
    point without looking at every box."""

    def __init__(self, cell):
        self.cell = cell
        self.cells = {}
        self.oversized = []
        self.boxes = {}

    def add(self, index, lo, hi):
        self.boxes[index] = (lo, hi)
        k_lo = [math.floor(c / self.cell) for c in lo]
        k_hi = [math.floor(c / self.cell) for c in hi]
        count = 1
        for a, b in zip(k_lo, k_hi):
            count *= b - a + 1
        if count > MAX_CELLS_PER_FACE:
            self.oversized.append(index)
            return
        for kx in range(k_lo[0], k_hi[0] + 1):
            for ky in range(k_lo[1], k_hi[1] + 1):
                for kz in range(k_lo[2], k_hi[2] + 1):
                    self.cells.setdefault((kx, ky, kz), []).append(index)

    def holding(self, p):
        key = tuple(math.floor(c / self.cell) for c in p)
        candidates = self.cells.get(key, []) + self.oversized
        found = []
        for index in candidates:
            lo, hi = self.boxes[index]
            if all(lo[i] <= p[i] <= hi[i] for i in range(3)):
                found.append(index)
        return found
