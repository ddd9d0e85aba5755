"""Mesh problems in Blender's own numbering (issue 20). The native validator
counts loop triangles and their edges; the artist's mesh has polygons and
edges, and a quad's diagonal is no Blender edge at all, so its numbers made
Select Non Manifold and the Spreadsheet show other elements. Vertices are
numbered alike on both sides (the operators send the mesh's own vertices)."""
import numpy as np

SHOWN = 8  # numbers listed before "and N more"


class MeshNumbering:
    """Maps the native report's triangles and vertex pairs to `mesh`'s
    polygons and edges; `tri_poly` gives each loop triangle's polygon."""

    def __init__(self, mesh, tri_poly, F):
        self.tri_poly = np.asarray(tri_poly, dtype=np.int64)
        self.F = np.asarray(F, dtype=np.int64)
        edge_vertices = np.empty(2 * len(mesh.edges), dtype=np.int64)
        mesh.edges.foreach_get("vertices", edge_vertices)
        edge_vertices = np.sort(edge_vertices.reshape(-1, 2), axis=1)
        self._n = max(len(mesh.vertices), 1)
        keys = edge_vertices[:, 0] * self._n + edge_vertices[:, 1]
        self._order = np.argsort(keys)
        self._keys = keys[self._order]
        self.areas = np.empty(len(mesh.polygons), dtype=np.float64)
        mesh.polygons.foreach_get("area", self.areas)

    def flat(self, polygons):
        """Which of the polygons have (near) zero area themselves, against the
        mesh's median: a quad with three corners in a line has a zero-area
        triangle but not a zero area."""
        typical = float(np.median(self.areas)) if len(self.areas) else 0.0
        return self.areas[np.asarray(polygons, dtype=np.int64)] <= 1e-6 * typical

    def polygons(self, triangles):
        """Sorted polygons of the given loop triangles."""
        triangles = np.asarray(triangles, dtype=np.int64)
        return np.unique(self.tri_poly[triangles]) if len(triangles) else np.empty(0, np.int64)

    def edges(self, pairs):
        """(Blender edges on the vertex pairs, polygons whose inside holds the
        pairs that are no Blender edge: diagonals of a quad or an n-gon)."""
        pairs = np.sort(np.asarray(pairs, dtype=np.int64).reshape(-1, 2), axis=1)
        keys = pairs[:, 0] * self._n + pairs[:, 1]
        at = np.clip(np.searchsorted(self._keys, keys), 0, max(len(self._keys) - 1, 0))
        found = (self._keys[at] == keys) if len(self._keys) else np.zeros(len(keys), dtype=bool)
        inside = []
        for a, b in pairs[~found][:64]:  # a few suffice to name where they are
            holding = np.flatnonzero((self.F == a).any(axis=1) & (self.F == b).any(axis=1))
            inside.extend(self.tri_poly[holding])
        return np.unique(self._order[at[found]]), np.unique(np.asarray(inside, dtype=np.int64))


def listed(word, plural, indices):
    """'edge 4' / 'edges 4, 9, 12 and 3 more'."""
    indices = [int(i) for i in indices]
    if len(indices) == 1:
        return f"{word} {indices[0]}"
    shown = ", ".join(str(i) for i in indices[:SHOWN])
    more = len(indices) - SHOWN
    return f"{plural} {shown}" + (f" and {more} more" if more > 0 else "")


def _count(n, word, plural):
    return f"{n} {word if n == 1 else plural}"


SELECT_HINT = "Select > Select All by Trait > Non Manifold shows them"


def describe_problem(error_text, report, numbering):
    """The native mesh-problem message `error_text` rewritten with Blender's
    polygon and edge numbers from `report` (native.validate of the same
    triangles); None where it is not one of those messages."""
    if "naming one vertex twice" in error_text and len(report.repeated_vertex_faces):
        polygons = numbering.polygons(report.repeated_vertex_faces)
        return (f"mesh has {_count(len(polygons), 'polygon', 'polygons')} naming one vertex twice "
                f"({listed('polygon', 'polygons', polygons)}): Mesh > Clean Up > Degenerate Dissolve "
                "removes them")
    if "duplicate face" in error_text and len(report.duplicate_faces):
        polygons = numbering.polygons(report.duplicate_faces)
        return (f"mesh has {_count(len(polygons), 'polygon', 'polygons')} on the same corners as another "
                f"({listed('polygon', 'polygons', polygons)}, enclosing nothing): delete the extra copies")
    if "shared by more than two faces" in error_text and len(report.non_manifold_edge_vertices):
        edges, inside = numbering.edges(report.non_manifold_edge_vertices)
        where = [listed("edge", "edges", edges)] if len(edges) else []
        where += [f"inside {listed('polygon', 'polygons', inside)}"] if len(inside) else []
        count = len(report.non_manifold_edge_vertices)
        return (f"mesh is not manifold: {_count(count, 'edge has', 'edges have')} more than two faces "
                f"({'; '.join(where)}): {SELECT_HINT}; delete or separate the extra faces")
    if "do not form a single fan" in error_text and len(report.non_manifold_vertices):
        vertices = report.non_manifold_vertices
        return (f"mesh is not manifold: surfaces touch at only "
                f"{_count(len(vertices), 'vertex', 'vertices')} ({listed('vertex', 'vertices', vertices)}): "
                f"{SELECT_HINT}; split or merge them")
    if "not consistently oriented" in error_text and len(report.inconsistent_orientation_edge_vertices):
        edges, inside = numbering.edges(report.inconsistent_orientation_edge_vertices)
        where = [listed("edge", "edges", edges)] if len(edges) else []
        where += [f"inside {listed('polygon', 'polygons', inside)}"] if len(inside) else []
        return (f"mesh's faces point different ways across "
                f"{_count(len(report.inconsistent_orientation_edge_vertices), 'edge', 'edges')} ({'; '.join(where)}): "
                "Mesh > Normals > Recalculate Outside")
    if "degenerate face" in error_text and len(report.degenerate_faces):
        polygons = numbering.polygons(report.degenerate_faces)
        if numbering.flat(polygons).all():
            return (f"mesh has {_count(len(polygons), 'zero-area polygon', 'zero-area polygons')} "
                    f"({listed('polygon', 'polygons', polygons)}): Mesh > Clean Up > Degenerate Dissolve "
                    "fixes them")
        return (f"mesh has {_count(len(polygons), 'polygon', 'polygons')} with a corner on a straight line "
                f"between two others, so part of it has no area ({listed('polygon', 'polygons', polygons)}): "
                "Mesh > Clean Up > Limited Dissolve removes such corners, or move them")
    return None
