"""Morphing operators (thesis ch. 4; issue 16). The source is the selected mesh,
the target the active one.

- "Pick Pins" (morph/pins.py): a viewport tool; click a vertex of one object, then its partner
  on the other, and the morph takes the one exactly onto the other. "Add Pin"
  does the same from one selected vertex on each (Edit Mode) or from explicit
  indices (scripts).
- "Preview Matches": the automatic correspondence Morph To would choose, with
  every candidate it weighed and its score; its pairs are listed and drawn,
  and can be removed before morphing.
- "Morph To": a new object on the merged topology with shape keys from the
  source to the target, keyframed over a frame range.

Pins, pairs and candidates live in the scene (`scene.paramorph_matches`,
read and written through pin_store), so they are saved with the .blend. Nothing is written unless the native call
succeeded."""
import bpy
import numpy as np

from .. import bridge, messages, overlay, poll_reasons, repair_mesh
from ..native import native
from ..native_operator import NativeOperator, UserError, numbering_for
from . import job, result_object
from .pin_store import add_pair, add_pin, claim, constraints, pin_array, two_objects


def _arrays(context, obj):
    with bridge.object_mode(context, obj):
        return bridge.mesh_arrays(obj.data, polygons=True, loops=True)


def linear_part(obj):
    """The 3 x 3 rotation and scale of an object's transform (no translation)."""
    return np.array(obj.matrix_world, dtype=np.float64)[:3, :3]


def turn_part(obj):
    """The rotation of an object's transform, without its scale (the polar
    factor of linear_part; a mirroring scale stays in it)."""
    u, _, vt = np.linalg.svd(linear_part(obj))
    return u @ vt


as_placed = bridge.as_placed  # a target scaled x9 and turned 45 deg is morphed to as it looks


def candidate_line(candidate):
    """'extremities — 6 of 7 and 7 tips paired, 2 deg apart, score 0.67' (a native or a stored candidate)."""
    head = f"{candidate.kind} — {candidate.detail}" if candidate.detail else candidate.kind
    if candidate.rejected:
        return f"{head}, rejected: {candidate.rejected}"
    return f"{head}, score {candidate.score:.3g}"


def _count(n, word):
    return f"{n} {word}{'' if n == 1 else 's'}"


def inside_out_note(result, source, target):
    """"Horse's faces pointed inwards: turned for the morph" for each inside-out file."""
    turned = [o.name for o, flag in ((source, result.inside_out_a), (target, result.inside_out_b)) if flag]
    return [f"{name}'s faces pointed inwards: turned for the morph" for name in turned]


def _removed_parts(change):
    """"2 smaller parts (112 faces)" from Repair's "removed 2 smaller parts
    (112 faces), kept the largest", else None."""
    if change.startswith("removed ") and "smaller part" in change and ", kept the largest" in change:
        return change[len("removed "):change.index(", kept the largest")]
    return None


def repair_notes(fixed_a, fixed_b, source, target, riding=False):
    """"Horse repaired: merged 12 vertices ..." for each mesh Repair changed.
    With `riding` (Morph To: the source's smaller parts ride along, which
    parts_notes says), the parts Repair left out of the source are not
    called removed, and the target's are said to be left out of the morph."""
    if not riding:
        return [f"{o.name} {fixed.summary()}" for o, fixed in ((source, fixed_a), (target, fixed_b))
                if fixed is not None and fixed.changed]
    notes = []
    for obj, fixed in ((source, fixed_a), (target, fixed_b)):
        if fixed is None:
            continue
        kept, left_out = [], []
        for change in fixed.changes:
            removed = _removed_parts(change)
            if removed is None:
                kept.append(change)
            elif obj is target:
                left_out.append(f"{target.name}'s {removed} are left out: the morph goes to its largest part")
        notes += ([f"{obj.name} repaired: " + "; ".join(kept)] if kept else []) + left_out
    return notes


def parts_notes(parts, source):
    """What became of the source's separate parts (job.RidingParts):
    "2 separate parts of Suzanne (68 vertices) ride along its body", those
    far from it that stay where they were, and which part was taken as the
    body when it holds under half of the source's vertices."""
    if parts is None:
        return []
    notes = []
    total = len(source.data.vertices)
    body = total - len(parts.vertices)
    if body < total / 2:  # e.g. a scatter of equal pieces: say which one was morphed
        notes.append(f"the morph takes {source.name}'s largest part ({body} of its {total} vertices) as its body")
    riding = np.flatnonzero(parts.riding & parts.separate)
    if len(riding):
        vertices = int(np.isin(parts.part_of, riding).sum())
        line = (f"{_count(len(riding), 'separate part')} of {source.name} "
                f"({vertices} {'vertex' if vertices == 1 else 'vertices'}) ride along its body")
        pushed = int(np.count_nonzero(parts.pushed[riding] > 0))
        if pushed:
            line += f" ({pushed} kept from sinking into it)"
        notes.append(line)
    left = int(np.count_nonzero(~parts.riding & parts.separate))
    if left:
        notes.append(f"{_count(left, 'part')} of {source.name} far from its body "
                     f"{'stays where it was' if left == 1 else 'stay where they were'}")
    return notes


# --- operators -----------------------------------------------------------------------

class CorrespondenceSettings:
    """The native correspondence's candidate switches, as operator properties
    (mixin for Preview Matches and Morph To; names mirror morph()'s keywords)."""

    extremities: bpy.props.BoolProperty(
        name="Extremities", default=True,
        description="Weigh pairings of the extremity tips (limbs, head, tail) of both meshes, by where they "
                    "lie on the sphere maps and by the paths from the body out to them")
    registration: bpy.props.BoolProperty(
        name="Registration", default=True,
        description="Weigh 3D registrations of the two shapes (as placed, and by principal axes)")
    features: bpy.props.BoolProperty(
        name="Feature Points", default=True,
        description="Weigh the pairing of feature points (creases, pockets) of both meshes")
    repair: repair_mesh.REPAIR_PROPERTY
    proxy_faces: bpy.props.IntProperty(
        name="Proxy Faces", default=3000, min=500, soft_max=20000,
        description="Faces of the simplified copies the candidates are scored on (more: slower, "
                    "finer; a smaller mesh is its own proxy)")

    def correspondence_options(self):
        return {"extremities": self.extremities, "registration": self.registration,
                "features": self.features, "proxy_faces": self.proxy_faces}


class _TwoMeshes(NativeOperator):
    constraints = "pins"  # its ConstraintErrors name the pins and pairs that cannot be met

    @classmethod
    def poll(cls, context):
        return poll_reasons.two_meshes(cls, context)

    def describe_error(self, error, state):
        # The native side names the mesh ("mesh A: ..."/"mesh B: ..."): report it by object.
        text = str(error)
        pair = f"{state['source']} → {state['target']}"
        if isinstance(error, native.ConstraintError):  # a vertex pinned twice, mirrored pins, folds
            for tag, side in (("mesh A: ", "source"), ("mesh B: ", "target")):
                if text.startswith(tag):
                    text = f"{state[side]}: {text[len(tag):]}"
            named = _with_text(error, f"{text} (A: {state['source']}, B: {state['target']})")
            return f"{pair}: {messages.describe(named, constraints=self.constraints)}"
        for tag, side in (("mesh A: ", "source"), ("mesh B: ", "target")):
            if text.startswith(tag):
                stripped = _with_text(error, text[len(tag):])
                arrays = state['arrays_' + side]
                described = messages.describe(stripped, *arrays, repair=getattr(self, "repair", None),
                                              numbering=numbering_for(stripped, state[side], arrays[1]))
                return f"{state[side]}: {described}"
        if isinstance(error, native.InvalidInputError):  # pins or pairs out of range
            return f"{pair}: {text} (A: {state['source']}, B: {state['target']})"
        described = messages.describe(error, repair=getattr(self, "repair", None))
        return described if isinstance(error, native.Cancelled) else f"{pair}: {described}"


def _with_text(error, text):
    """The same kind of error with a new message (the mesh tag taken off)."""
    try:
        return type(error)(text)
    except Exception:
        return error


class PARAMORPH_OT_preview_matches(_TwoMeshes, CorrespondenceSettings, bpy.types.Operator):
    """Find the correspondence Morph To would use for the selected mesh (source) and the
    active mesh (target): every automatic candidate with its score, the chosen one's pairs
    listed and drawn. Your pins are kept and taken into account"""
    bl_idname = "paramorph.preview_matches"
    bl_label = "Preview Matches"
    bl_options = {"REGISTER", "UNDO"}

    def prepare(self, context):
        source, target = two_objects(context)
        pins, _ = constraints(context, source, target, use_pairs=False)
        VA, FA, _, _ = _arrays(context, source)
        VB, FB, _, _ = _arrays(context, target)
        VA, VB = as_placed(VA, source), as_placed(VB, target)
        state = {"source": source.name, "target": target.name, "arrays_source": (VA, FA),
                 "arrays_target": (VB, FB), "pins": pins, "objects": [source.name, target.name]}
        options = dict(self.correspondence_options(), pins=pins, repair=self.repair)
        return job.correspondence, (VA, FA, VB, FB), options, state

    def finish(self, context, outcome, state):
        result, fixed_a, fixed_b = outcome
        source, target = bpy.data.objects[state["source"]], bpy.data.objects[state["target"]]
        matches = claim(context.scene.paramorph_matches, source, target)
        for i in reversed(range(len(matches.pairs))):  # the pins stay, the old automatic pairs go
            if not matches.pairs[i].pin:
                matches.pairs.remove(i)
        matches.candidates.clear()
        candidates = result.candidates  # a new list per access
        for i, c in enumerate(candidates):
            item = matches.candidates.add()
            item.kind, item.detail, item.rejected = c.kind, c.detail, c.rejected
            item.score, item.distortion = c.score, c.distortion  # inf (rejected) is stored as FLT_MAX
            item.chosen, item.pairs = i == result.chosen, len(c.proxy_pairs)
        chosen = candidates[result.chosen]
        pairs = np.asarray(result.pairs).reshape(-1, 2)
        if fixed_a is not None:  # on the mended meshes' vertices: back onto the objects'
            pairs = fixed_a.vertex_pairs_back(pairs, fixed_b)
        pins = pin_array(matches)
        for a, b in pairs:
            if a not in pins[:, 0] and b not in pins[:, 1]:
                add_pair(matches, int(a), int(b), kind=chosen.kind)
        matches.pair_index = min(matches.pair_index, max(len(matches.pairs) - 1, 0))
        overlay.tag_redraw(context)
        none = next((c for c in candidates if c.kind == "none"), None)
        against = f" (no pairs: {none.score:.3g})" if none is not None and chosen.kind != "none" else ""
        notes = inside_out_note(result, source, target) + repair_notes(fixed_a, fixed_b, source, target)
        return (f"Preview Matches: chosen {candidate_line(chosen)}{against}; "
                f"{_count(len(matches.pairs) - len(pins), 'pair')}, {_count(len(pins), 'pin')}"
                + "".join(f"; {n}" for n in notes))


def _selected_vertex(context, obj):
    """The one selected vertex of `obj` (in Edit Mode too), or a UserError."""
    if obj.mode == "EDIT":
        obj.update_from_editmode()
    selected = np.empty(len(obj.data.vertices), dtype=bool)
    obj.data.vertices.foreach_get("select", selected)
    chosen = np.flatnonzero(selected)
    if len(chosen) != 1:
        raise UserError(f"select exactly one vertex on {obj.name} ({len(chosen)} selected)")
    return int(chosen[0])


def _given_vertex(obj, vertex):
    if vertex >= len(obj.data.vertices):
        raise UserError(f"{obj.name} has no vertex {vertex} (it has {len(obj.data.vertices)})")
    return vertex


class PARAMORPH_OT_add_pin(bpy.types.Operator):
    """Pin a vertex of the source to a vertex of the target: the morph takes one exactly
    onto the other (one vertex selected on each object in Edit Mode, or given by index)"""
    bl_idname = "paramorph.add_pin"
    bl_label = "Add Pin"
    bl_options = {"REGISTER", "UNDO"}

    vertex_a: bpy.props.IntProperty(
        name="Source Vertex", default=-1, min=-1,
        description="Vertex of the source to pin (-1: the one selected in Edit Mode)")
    vertex_b: bpy.props.IntProperty(
        name="Target Vertex", default=-1, min=-1,
        description="Vertex of the target it lands on (-1: the one selected in Edit Mode)")

    @classmethod
    def poll(cls, context):
        return poll_reasons.two_meshes(cls, context)

    def execute(self, context):
        try:
            source, target = two_objects(context)
            a = _given_vertex(source, self.vertex_a) if self.vertex_a >= 0 else _selected_vertex(context, source)
            b = _given_vertex(target, self.vertex_b) if self.vertex_b >= 0 else _selected_vertex(context, target)
        except UserError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        matches = claim(context.scene.paramorph_matches, source, target)
        replaced = add_pin(matches, a, b)
        overlay.tag_redraw(context)
        self.report({"INFO"}, f"pinned {source.name} vertex {a} to {target.name} vertex {b}"
                              + (f" (replacing {_count(replaced, 'pair')} on those vertices)" if replaced else ""))
        return {"FINISHED"}


class PARAMORPH_OT_remove_pair(bpy.types.Operator):
    """Remove the chosen pin or pair from the list (the morph will not use it)"""
    bl_idname = "paramorph.remove_pair"
    bl_label = "Remove Pair"
    bl_options = {"REGISTER", "UNDO"}

    index: bpy.props.IntProperty(name="Pair", default=-1, min=-1,
                                 description="Row to remove (-1: the one chosen in the list)")

    @classmethod
    def poll(cls, context):
        return len(context.scene.paramorph_matches.pairs) > 0 or poll_reasons.refuse(
            cls, "The list has no pins or pairs: Pick Pins or Preview Matches first")

    def execute(self, context):
        matches = context.scene.paramorph_matches
        index = matches.pair_index if self.index < 0 else self.index
        if not 0 <= index < len(matches.pairs):
            self.report({"ERROR"}, f"no pair {index} (there are {len(matches.pairs)})")
            return {"CANCELLED"}
        matches.pairs.remove(index)
        matches.pair_index = min(index, max(len(matches.pairs) - 1, 0))
        overlay.tag_redraw(context)
        return {"FINISHED"}


class PARAMORPH_OT_clear_pins(bpy.types.Operator):
    """Remove every pin (the previewed automatic pairs stay)"""
    bl_idname = "paramorph.clear_pins"
    bl_label = "Clear Pins"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return any(p.pin for p in context.scene.paramorph_matches.pairs) or poll_reasons.refuse(
            cls, "There are no pins to clear")

    def execute(self, context):
        matches = context.scene.paramorph_matches
        for i in reversed(range(len(matches.pairs))):
            if matches.pairs[i].pin:
                matches.pairs.remove(i)
        matches.pair_index = min(matches.pair_index, max(len(matches.pairs) - 1, 0))
        overlay.tag_redraw(context)
        return {"FINISHED"}


class PARAMORPH_OT_clear_matches(bpy.types.Operator):
    """Forget the pins, the previewed pairs and the candidates"""
    bl_idname = "paramorph.clear_matches"
    bl_label = "Clear Matches"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        matches = context.scene.paramorph_matches
        matches.pairs.clear()
        matches.candidates.clear()
        matches.source = matches.target = None
        overlay.tag_redraw(context)
        return {"FINISHED"}


class PARAMORPH_OT_morph_to(_TwoMeshes, CorrespondenceSettings, bpy.types.Operator):
    """Morph the selected mesh into the active one: a new object on a merged topology with
    shape keys from the source's shape through in-betweens to the target's, driven by one
    property keyframed over a frame range; your pins hold exactly"""
    bl_idname = "paramorph.morph_to"
    bl_label = "Morph To"
    bl_options = {"REGISTER", "UNDO"}

    frame_start: bpy.props.IntProperty(name="Start Frame", default=1, description="Frame where the morph starts")
    frame_end: bpy.props.IntProperty(name="End Frame", default=48, description="Frame where it reaches the target")
    in_betweens: bpy.props.IntProperty(
        name="In-Betweens", default=8, min=0, max=32,
        description="Shape keys between source and target, evenly spaced and driven in order by the "
                    "object's morph property: scrubbing plays them, and you can sculpt them")
    interpolation: bpy.props.EnumProperty(
        name="In-Betweens", default="ARAP",
        items=(("ARAP", "As Rigid As Possible", "Parts turn and keep their shape on the way "
                "(per-face rotations interpolated, one solve per key)"),
               ("LINEAR", "Straight Lines", "Every point on a straight line (the thesis'; limbs that "
                "turn get shorter and may pass through the body)")))
    easing: bpy.props.EnumProperty(
        name="Timing", default="EASE",
        items=(("LINEAR", "Linear", "Constant speed"),
               ("EASE", "Eased", "Start and end slowly (Bezier)")))
    topology: bpy.props.EnumProperty(
        name="Topology", default="AUTO",
        items=(("AUTO", "Automatic", "Keep the source's topology when it has an armature, vertex groups or "
                "UV layers, else a merged one"),
               ("KEEP", "Keep Source's", "Shape keys on the source object itself (the target's shape at its "
                "vertices): its rig, vertex groups, UVs, modifiers and normals stay as they are"),
               ("MERGED", "Merged", "A new object on a merged topology holding both meshes' detail")))
    placement: bpy.props.EnumProperty(
        name="End At", default="SOURCE",
        items=(("SOURCE", "Source's Place", "The target's shape, in the source's place"),
               ("TARGET", "Target's Place", "The morph ends where the target object is")))
    automatic: bpy.props.BoolProperty(
        name="Automatic Matching", default=True,
        description="Choose the correspondence among automatic candidates (extremity tips, registrations, "
                    "feature points, none) by the distortion each makes; off: only your pins and the "
                    "objects' placement decide")
    use_preview: bpy.props.BoolProperty(
        name="Use Previewed Pairs", default=True,
        description="Use the automatic pairs of Preview Matches for these two objects, as edited, instead "
                    "of choosing again (your pins are always used)")

    def invoke(self, context, event):
        if not self.properties.is_property_set("frame_start"):
            self.frame_start = context.scene.frame_start
        if not self.properties.is_property_set("frame_end"):
            self.frame_end = max(context.scene.frame_end, self.frame_start + 1)
        return super().invoke(context, event)

    def prepare(self, context):
        if self.frame_end <= self.frame_start:
            raise UserError("End Frame must come after Start Frame")
        source, target = two_objects(context)
        pins, pairs = constraints(context, source, target, use_pairs=self.use_preview and self.automatic)
        VA, FA, tri_poly, tri_loops = _arrays(context, source)
        VB, FB, _, _ = _arrays(context, target)
        # Computed with each object's rotation and scale applied, about its
        # origin; the keys go back into the source's own coordinates.
        VA, VB = as_placed(VA, source), as_placed(VB, target)
        keep = self.topology == "KEEP" or (self.topology == "AUTO" and keeps_topology(source))
        options = dict(self.correspondence_options(), automatic=self.automatic, pins=pins,
                       in_betweens=self.in_betweens, interpolation=self.interpolation, keep_topology=keep,
                       repair=self.repair)
        if pairs is not None:
            options["pairs"] = pairs
        options["to_local"] = np.linalg.inv(linear_part(source))
        options["target_turn"] = turn_part(target)  # its distance reported on its own box, however turned
        if self.placement == "TARGET":  # the offset between the two origins, in the scene
            offset = np.eye(4)
            offset[:3, 3] = np.array(target.matrix_world.translation) - np.array(source.matrix_world.translation)
            options["target_transform"] = offset
        state = {"source": source.name, "target": target.name, "arrays_source": (VA, FA),
                 "arrays_target": (VB, FB), "tri_poly": tri_poly, "tri_loops": tri_loops,
                 "previewed": pairs is not None, "objects": [source.name, target.name]}
        return job.morph_with_in_betweens, (VA, FA, VB, FB), options, state

    def finish(self, context, outcome, state):
        source, target = bpy.data.objects[state["source"]], bpy.data.objects[state["target"]]
        result = outcome.result
        notes = (repair_notes(outcome.repaired_a, outcome.repaired_b, source, target, riding=True)
                 + parts_notes(outcome.parts, source))
        if outcome.keep_topology:
            result_object.add_morph_keys(context, source, outcome.shapes, outcome.target, target_name=target.name,
                                        frame_start=self.frame_start, frame_end=self.frame_end,
                                        easing=self.easing == "EASE")
            report, coarse = keep_report(source, target, outcome, state["previewed"], notes)
            if coarse:
                self.report({"WARNING"}, coarse)
            return report
        tri_poly, tri_loops = state["tri_poly"], state["tri_loops"]
        if outcome.repaired_a is not None:  # the merged faces come from the mended source's triangles
            tri_poly, tri_loops = outcome.repaired_a.triangle_maps(tri_poly, tri_loops)
        obj = result_object.build(
            context, f"{source.name} to {target.name}", source, result, outcome.target, outcome.shapes,
            tri_poly=tri_poly, tri_loops=tri_loops, target_name=target.name, source_positions=outcome.source,
            frame_start=self.frame_start, frame_end=self.frame_end, easing=self.easing == "EASE",
            parts=outcome.parts, source_triangles=(state["tri_poly"], state["tri_loops"], state["arrays_source"][1]))
        for other in context.view_layer.objects:  # objects, not mesh elements
            other.select_set(other == obj)
        context.view_layer.objects.active = obj
        input_faces = len(state["arrays_source"][1]) + len(state["arrays_target"][1])
        return morph_report(obj, result, source, target, state["previewed"], input_faces, notes)


# The last finished Morph To in this session: {"object", "chosen", "held", "notes"}
# (the batch CLI prints it; scripts may read it). None before the first.
last_morph = None


# How far (share of the target's diagonal) parts of the target may lie from
# the morphed shape on a kept topology before Morph To warns. Measured on
# generated quadrupeds kept at 6k faces onto 12-20k: 1.2 % (chords across
# the target's facets, vertices spread unevenly by the correspondence);
# a horse onto a cow, whose horns it has no vertices for: 2.2 %.
COARSE_SHARE = 0.02
# A kept topology with more of its faces than this folded against the target
# gets a note: they shade as creases (Merged has none).
FOLDED_SHARE = 0.01


def keeps_topology(obj):
    """Morph To's automatic choice: the source's own topology when something
    hangs on it (an armature, vertex groups, UV layers)."""
    rigged = obj.find_armature() is not None or any(m.type == "ARMATURE" for m in obj.modifiers)
    return rigged or len(obj.vertex_groups) > 0 or len(obj.data.uv_layers) > 0


def keep_report(source, target, outcome, previewed=False, repaired=()):
    """(INFO line, WARNING line or None) for a morph onto the source's own topology."""
    global last_morph
    result = outcome.result
    share = outcome.distance.hausdorff / max(outcome.target_diagonal, 1e-300)
    missed = outcome.distance.b_to_a / max(outcome.target_diagonal, 1e-300)
    pins = int(np.count_nonzero(np.asarray(result.pair_is_pin)))
    pairs = len(result.pairs) - pins
    chosen = result.candidates[result.chosen]
    how = "previewed pairs" if previewed else "chosen"
    held = f"{_count(pins, 'pin')} and {_count(pairs, 'pair')} held exactly"
    notes = inside_out_note(result, source, target) + list(repaired) + fallback_notes(result, source, target)
    if outcome.folded > FOLDED_SHARE:
        notes.append(f"{100 * outcome.folded:.2g} % of its faces lie folded against the target (they shade as "
                     "creases; Topology: Merged has none)")
    keys = len(outcome.shapes) + 1
    last_morph = {"object": source.name, "chosen": f"{how} {candidate_line(chosen)}", "held": held, "notes": notes,
                  "hausdorff": share, "folded": outcome.folded}
    line = (f"Morph To: {source.name} keeps its topology ({len(source.data.vertices)} vertices), "
            f"{_count(keys, 'shape key')} to {target.name}; {how} {candidate_line(chosen)}; {held}; "
            f"Hausdorff distance to the target {100 * share:.2g} % of its diagonal"
            + "".join(f"; {n}" for n in notes))
    coarse = None
    if missed > COARSE_SHARE:
        coarse = (f"{source.name} is too coarse for {target.name}'s detail: parts of the target lie "
                  f"{100 * missed:.2g} % of its diagonal from the morphed shape (the source's vertices do not "
                  "reach them); Topology: Merged keeps both meshes' detail")
    return line, coarse


def fallback_notes(result, source, target):
    """What the morph fell back on (Morph.fallbacks), with the objects' names
    for "mesh A" and "mesh B"."""
    names = {"mesh A:": f"{source.name}:", "mesh B:": f"{target.name}:"}
    notes = []
    for note in getattr(result, "fallbacks", ()):
        head = note[:7]
        notes.append(names[head] + note[7:] if head in names else note)
    return notes


def morph_report(obj, result, source, target, previewed=False, input_faces=0, repaired=()):
    """Morph To's one-line report: the merged faces against the inputs', the chosen
    candidate, what holds exactly, inside-out files, time."""
    global last_morph
    pins = int(np.count_nonzero(np.asarray(result.pair_is_pin)))
    pairs = len(result.pairs) - pins
    chosen = result.candidates[result.chosen]
    how = "previewed pairs" if previewed else "chosen"
    held = f"{_count(pins, 'pin')} and {_count(pairs, 'pair')} held exactly"
    seconds = result.timings[-1][1] if result.timings else 0.0
    notes = inside_out_note(result, source, target) + list(repaired) + fallback_notes(result, source, target)
    last_morph = {"object": obj.name, "chosen": f"{how} {candidate_line(chosen)}", "held": held, "notes": notes}
    size = f" ({len(result.faces) / input_faces:.1f}x the inputs' {input_faces})" if input_faces else ""
    welded = result.weld.collapsed_edges
    size += f", {_count(welded, 'short edge')} welded" if welded else ""
    return (f"Morph To: {obj.name}, {len(result.faces)} faces{size}; {how} {candidate_line(chosen)}; {held}"
            + "".join(f"; {n}" for n in notes) + f"; {seconds:.1f} s")


classes = (PARAMORPH_OT_preview_matches, PARAMORPH_OT_add_pin, PARAMORPH_OT_remove_pair,
           PARAMORPH_OT_clear_pins, PARAMORPH_OT_clear_matches, PARAMORPH_OT_morph_to)
