"""The morph's pins and pairs (issue 16): the scene's list
(`scene.paramorph_matches`, saved with the .blend) of which vertex of the
source goes to which of the target, read and written here for Preview
Matches, Morph To, Add Pin and Pick Pins alike; and the Pick Pins session
that is running, if any, for the overlay to draw. It imports no operator
module, so the operators and the overlay can all import it."""
import numpy as np

from ..native_operator import UserError

# The Pick Pins session that is running (a pins.PinPicker), else None:
# the overlay draws its marks.
active_picker = None


def set_active_picker(picker):
    global active_picker
    active_picker = picker


def two_objects(context):
    """(source, target): the selected mesh that is not active, and the active mesh."""
    target = context.active_object
    others = [o for o in context.selected_objects if o != target]
    if target is None or target.type != "MESH" or len(others) != 1 or others[0].type != "MESH":
        raise UserError("select two mesh objects: the source, then the target (active, selected last)")
    return others[0], target


def belongs_to(matches, source, target):
    """Whether the scene's list was made for these two objects (in this order)."""
    return matches.source == source and matches.target == target


def is_current(matches, source, target):
    """Whether the list's vertex indices were taken on these meshes as they are now."""
    return (belongs_to(matches, source, target) and matches.source_vertices == len(source.data.vertices)
            and matches.target_vertices == len(target.data.vertices))


def claim(matches, source, target):
    """The scene's list for these two objects: kept when it is theirs and current,
    else emptied (pins for other objects or other geometry mean nothing here)."""
    if not is_current(matches, source, target):
        matches.pairs.clear()
        matches.candidates.clear()
        matches.source, matches.target = source, target
        matches.source_vertices, matches.target_vertices = len(source.data.vertices), len(target.data.vertices)
        matches.pair_index = 0
    return matches


def add_pair(matches, vertex_a, vertex_b, pin=False, kind=""):
    item = matches.pairs.add()
    item.vertex_a, item.vertex_b, item.pin, item.kind = vertex_a, vertex_b, pin, kind
    return item


def add_pin(matches, vertex_a, vertex_b):
    """Pins vertex_a of the source to vertex_b of the target; the pin replaces
    every pair (automatic or pin) on either vertex. Returns how many it replaced."""
    replaced = 0
    for i in reversed(range(len(matches.pairs))):
        if matches.pairs[i].vertex_a == vertex_a or matches.pairs[i].vertex_b == vertex_b:
            matches.pairs.remove(i)
            replaced += 1
    add_pair(matches, vertex_a, vertex_b, pin=True)
    matches.pair_index = len(matches.pairs) - 1
    return replaced


_CANDIDATE_FIELDS = ("kind", "detail", "score", "distortion", "rejected", "chosen", "pairs")


def snapshot(matches):
    """Everything in the scene's list, to put back with restore() (a cancelled Pick Pins)."""
    return {"source": matches.source, "target": matches.target,
            "vertices": (matches.source_vertices, matches.target_vertices), "pair_index": matches.pair_index,
            "pairs": [(p.vertex_a, p.vertex_b, p.pin, p.kind) for p in matches.pairs],
            "candidates": [tuple(getattr(c, name) for name in _CANDIDATE_FIELDS) for c in matches.candidates]}


def restore(matches, saved):
    matches.source, matches.target = saved["source"], saved["target"]
    matches.source_vertices, matches.target_vertices = saved["vertices"]
    matches.pairs.clear()
    for a, b, pin, kind in saved["pairs"]:
        add_pair(matches, a, b, pin=pin, kind=kind)
    matches.candidates.clear()
    for values in saved["candidates"]:
        item = matches.candidates.add()
        for name, value in zip(_CANDIDATE_FIELDS, values):
            setattr(item, name, value)
    matches.pair_index = saved["pair_index"]


def pin_array(matches):
    """(k, 2) int32 pins in list order (native numbers them so: "pin 0" is the first)."""
    return np.array([(p.vertex_a, p.vertex_b) for p in matches.pairs if p.pin], dtype=np.int32).reshape(-1, 2)


def pair_array(matches):
    """(k, 2) int32 automatic (previewed) pairs, without those sharing a vertex with a pin."""
    pins = pin_array(matches)
    return np.array([(p.vertex_a, p.vertex_b) for p in matches.pairs if not p.pin
                     and p.vertex_a not in pins[:, 0] and p.vertex_b not in pins[:, 1]],
                    dtype=np.int32).reshape(-1, 2)


def check_indices(matches, source, target):
    """UserError naming the object and the row when an (edited) index is not a vertex."""
    na, nb = len(source.data.vertices), len(target.data.vertices)
    pin = 0
    for row, p in enumerate(matches.pairs):
        label = f"pin {pin}" if p.pin else f"pair {row}"
        for obj, vertex, count in ((source, p.vertex_a, na), (target, p.vertex_b, nb)):
            if vertex >= count:
                raise UserError(f"{label} ({p.vertex_a}, {p.vertex_b}): {obj.name} has no vertex {vertex} "
                                f"(it has {count}): edit or remove it in the Paramorph panel")
        pin += p.pin


def constraints(context, source, target, use_pairs):
    """(pins, pairs or None) for a native call on these two objects: the scene's
    pins when the list is theirs, and its previewed pairs when `use_pairs` and
    there are some. Pins picked on other geometry are an error, not ignored."""
    matches = context.scene.paramorph_matches
    if not belongs_to(matches, source, target) or not len(matches.pairs):
        return np.zeros((0, 2), dtype=np.int32), None
    if not is_current(matches, source, target):
        if any(p.pin for p in matches.pairs):
            raise UserError(
                f"the pins of {source.name} → {target.name} were picked on {matches.source_vertices} and "
                f"{matches.target_vertices} vertices, the meshes have {len(source.data.vertices)} and "
                f"{len(target.data.vertices)} now: Clear Pins and pick them again")
        return np.zeros((0, 2), dtype=np.int32), None
    check_indices(matches, source, target)
    pairs = pair_array(matches) if use_pairs else None
    return pin_array(matches), pairs if pairs is not None and len(pairs) else None
