"""Region labels on Blender meshes: the integer face attribute that stores
them, region adjacency, and selecting faces by region. numpy only; no Python
loops over elements."""
import colorsys

import numpy as np

ATTRIBUTE = "paramorph_region"
COLOR_ATTRIBUTE = "paramorph_region_color"
FEATURE_POINT_ATTRIBUTE = "paramorph_feature_point"


def region_colors(count, alpha=1.0):
    """Distinct colours: hues spread by the golden ratio, strong saturation."""
    hues = (np.arange(count) * 0.618033988749895) % 1.0
    rgb = np.array([colorsys.hsv_to_rgb(h, 0.85, 1.0) for h in hues], dtype=np.float32)
    return np.hstack([rgb.reshape(-1, 3), np.full((count, 1), alpha, dtype=np.float32)])


def polygon_labels(mesh, triangle_labels, tri_poly):
    """Per-polygon labels from per-loop-triangle labels: the label most of a
    polygon's triangles carry (an n-gon split across regions goes whole)."""
    P = len(mesh.polygons)
    labels = np.zeros(P, dtype=np.int32)
    if len(tri_poly) == P:  # all triangles: one each
        labels[tri_poly] = triangle_labels
        return labels
    regions = int(triangle_labels.max()) + 1 if len(triangle_labels) else 1
    counts = np.bincount(tri_poly.astype(np.int64) * regions + triangle_labels,
                         minlength=P * regions).reshape(P, regions)
    return counts.argmax(axis=1).astype(np.int32)


def attribute_for_writing(mesh, name, data_type, domain):
    """The attribute `name` with this type and domain: reused, or (re)created."""
    attribute = mesh.attributes.get(name)
    if attribute is not None and (attribute.domain != domain or attribute.data_type != data_type):
        mesh.attributes.remove(attribute)
        attribute = None
    return attribute or mesh.attributes.new(name=name, type=data_type, domain=domain)


def write_labels(mesh, labels, name=ATTRIBUTE):
    """Stores per-polygon labels as an INT face attribute (kept on save)."""
    attribute = attribute_for_writing(mesh, name, "INT", "FACE")
    attribute.data.foreach_set("value", np.ascontiguousarray(labels, dtype=np.int32))
    mesh.update()


def write_feature_points(mesh, vertices, kinds, name=FEATURE_POINT_ATTRIBUTE):
    """Per vertex: +1 concave feature point, -1 convex, 0 none (INT point attribute)."""
    values = np.zeros(len(mesh.vertices), dtype=np.int32)
    values[np.asarray(vertices, dtype=np.int64)] = np.asarray(kinds, dtype=np.int32)
    attribute_for_writing(mesh, name, "INT", "POINT").data.foreach_set("value", values)


def write_label_colors(mesh, labels, name=COLOR_ATTRIBUTE):
    """The regions as a per-corner colour attribute, made the active colour,
    so Solid shading with Attribute colour and Workbench renders show them
    without the overlay."""
    # FLOAT_COLOR: foreach_set copies; BYTE_COLOR converts every value (20x slower).
    attribute = attribute_for_writing(mesh, name, "FLOAT_COLOR", "CORNER")
    loop_total = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_total", loop_total)
    colors = region_colors(int(labels.max()) + 1 if len(labels) else 1)
    attribute.data.foreach_set("color", colors[np.repeat(labels, loop_total)].ravel())
    if hasattr(mesh, "color_attributes"):  # 3.2+
        mesh.color_attributes.active_color = attribute
    mesh.update()


def read_labels(mesh, name=ATTRIBUTE):
    """Per-polygon labels, or None when the mesh has no segmentation."""
    attribute = mesh.attributes.get(name)
    if attribute is None or attribute.domain != "FACE" or len(attribute.data) != len(mesh.polygons):
        return None  # none, or in Edit Mode (the layer lives in the BMesh then)
    labels = np.empty(len(mesh.polygons), dtype=np.int32)
    attribute.data.foreach_get("value", labels)
    return labels


def polygon_pairs(mesh):
    """(k, 2) pairs of polygons sharing an edge (manifold edges)."""
    L = len(mesh.loops)
    edge = np.empty(L, dtype=np.int32)
    mesh.loops.foreach_get("edge_index", edge)
    loop_start = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_start", loop_start)
    loop_total = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_total", loop_total)
    poly = np.repeat(np.arange(len(loop_start), dtype=np.int32), loop_total)
    order = np.argsort(edge, kind="stable")
    e, p = edge[order], poly[order]
    shared = np.flatnonzero(e[1:] == e[:-1])
    return np.stack([p[shared], p[shared + 1]], axis=1)


def region_adjacency(mesh, labels):
    """Sorted unique (a < b) pairs of regions sharing an edge."""
    pairs = labels[polygon_pairs(mesh)]
    pairs = pairs[pairs[:, 0] != pairs[:, 1]]
    pairs.sort(axis=1)
    return np.unique(pairs, axis=0) if len(pairs) else pairs.reshape(0, 2)


def selected_polygons(mesh):
    selected = np.empty(len(mesh.polygons), dtype=bool)
    mesh.polygons.foreach_get("select", selected)
    return selected


def select_polygons(mesh, mask):
    """Selects exactly the polygons in `mask` (and their vertices and edges);
    object-mode data, so call with the object out of Edit Mode."""
    mask = np.ascontiguousarray(mask, dtype=bool)
    loop_vertex = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    loop_edge = np.empty(len(mesh.loops), dtype=np.int32)
    mesh.loops.foreach_get("edge_index", loop_edge)
    loop_total = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.polygons.foreach_get("loop_total", loop_total)
    loop_selected = np.repeat(mask, loop_total)
    vertices = np.zeros(len(mesh.vertices), dtype=bool)
    vertices[loop_vertex[loop_selected]] = True
    edges = np.zeros(len(mesh.edges), dtype=bool)
    edges[loop_edge[loop_selected]] = True
    mesh.vertices.foreach_set("select", vertices)
    mesh.edges.foreach_set("select", edges)
    mesh.polygons.foreach_set("select", mask)
    mesh.update()


def regions_mask(labels, regions):
    return np.isin(labels, np.asarray(list(regions), dtype=np.int32))


def grown(mesh, labels, selected):
    """Regions touched by the selection, completed; if that changes nothing,
    also their neighbouring regions."""
    touched = np.unique(labels[selected])
    complete = regions_mask(labels, touched)
    if not np.array_equal(complete, selected):
        return complete
    adjacency = region_adjacency(mesh, labels)
    near = adjacency[np.isin(adjacency, touched).any(axis=1)].ravel()
    return regions_mask(labels, np.union1d(touched, near))


def shrunk(mesh, labels, selected):
    """Only the regions entirely selected and not bordering an unselected
    region stay selected."""
    all_regions = np.unique(labels)
    partly = np.unique(labels[~selected])
    full = np.setdiff1d(all_regions, partly)
    adjacency = region_adjacency(mesh, labels)
    border = adjacency[np.isin(adjacency, full).any(axis=1) & np.isin(adjacency, partly).any(axis=1)]
    keep = np.setdiff1d(full, border.ravel())
    return regions_mask(labels, keep)
