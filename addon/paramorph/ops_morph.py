"""Morphing operators (thesis ch. 4): "Preview Matches" finds the feature
pairs of two selected meshes and shows them (regions coloured alike on both,
pairs as dots joined by lines); the user removes pairs or pins their own;
"Morph To" builds a new object on the merged topology with shape keys from
the source (the selected object) to the target (the active one), keyframed
over a frame range. Nothing is written unless the native call succeeded."""
import bpy
import numpy as np

from . import bridge, messages, morph_object, overlay, regions, sphere_cache
from .native import native
from .native_operator import NativeOperator, UserError
from .ops_segment import FeatureRegionSettings


def two_objects(context):
    """(source, target): the selected mesh that is not active, and the active mesh."""
    target = context.active_object
    others = [o for o in context.selected_objects if o != target]
    if target is None or target.type != "MESH" or len(others) != 1 or others[0].type != "MESH":
        raise UserError("select two mesh objects: the source, then the target (active, selected last)")
    return others[0], target


def _poll_two(context):
    target = context.active_object
    return (target is not None and target.type == "MESH" and len(context.selected_objects) == 2
            and all(o.type == "MESH" for o in context.selected_objects))


def _arrays(context, obj):
    with bridge.object_mode(context, obj):
        return bridge.mesh_arrays(obj.data, polygons=True, loops=True)


def stored_matches(context, source, target):
    """The preview's pairs when they belong to these two objects as they are now, else None."""
    matches = context.scene.paramorph_matches
    if (matches.source != source or matches.target != target
            or matches.source_vertices != len(source.data.vertices)
            or matches.target_vertices != len(target.data.vertices)):
        return None
    return matches


class _TwoMeshes(NativeOperator):
    @classmethod
    def poll(cls, context):
        return _poll_two(context)

    def describe_error(self, error, state):
        # The native side names the mesh ("mesh A: ..."/"mesh B: ..."): report it by object.
        text = str(error)
        for tag, side in (("mesh A", "source"), ("mesh B", "target")):
            if text.startswith(tag):
                return f"{state[side]}: {messages.describe(error, *state['arrays_' + side])}"
        return messages.describe(error)


class PARAMORPH_OT_preview_matches(_TwoMeshes, FeatureRegionSettings, bpy.types.Operator):
    """Match the feature regions and feature points of the selected mesh (source) and the
    active mesh (target), and show the pairs before morphing"""
    bl_idname = "paramorph.preview_matches"
    bl_label = "Preview Matches"
    bl_options = {"REGISTER", "UNDO"}

    def prepare(self, context):
        source, target = two_objects(context)
        VA, FA, tri_poly_a, _ = _arrays(context, source)
        VB, FB, tri_poly_b, _ = _arrays(context, target)
        options = self.feature_options()
        state = {"source": source.name, "target": target.name, "arrays_source": (VA, FA),
                 "arrays_target": (VB, FB), "tri_poly": (tri_poly_a, tri_poly_b)}
        # The pairs Morph To would make (B registered onto A, then feature points paired).
        return native.morph_pairs, (VA, FA, VB, FB), options, state

    def finish(self, context, result, state):
        match = result.match
        source, target = bpy.data.objects[state["source"]], bpy.data.objects[state["target"]]
        labels_a = np.asarray(match.labels_a)
        labels_b = np.asarray(match.labels_b)
        # Matched regions share a colour: B's matched regions take their A partner's label.
        relabel = np.arange(labels_b.max() + 1 if len(labels_b) else 0) + int(labels_a.max()) + 1
        for a, b in np.asarray(match.region_pairs).reshape(-1, 2):
            relabel[b] = a
        for obj, triangle_labels, tri_poly in ((source, labels_a, state["tri_poly"][0]),
                                               (target, relabel[labels_b], state["tri_poly"][1])):
            labels = regions.polygon_labels(obj.data, triangle_labels, tri_poly)
            with bridge.object_mode(context, obj):
                regions.write_labels(obj.data, labels)
                regions.write_label_colors(obj.data, labels)
            obj.paramorph_regions = int(labels.max()) + 1 if len(labels) else 0
            overlay.forget(obj.name)

        matches = context.scene.paramorph_matches
        pins = [(p.vertex_a, p.vertex_b) for p in matches.pairs if p.pin] \
            if stored_matches(context, source, target) else []
        matches.pairs.clear()
        matches.source, matches.target = source, target
        matches.source_vertices, matches.target_vertices = len(source.data.vertices), len(target.data.vertices)
        for a, b in pins:
            add_pair(matches, a, b, 0.0, pin=True)
        pairs = np.asarray(result.pairs).reshape(-1, 2)
        for (a, b), score in zip(pairs, result.scores):
            add_pair(matches, int(a), int(b), float(score))
        overlay.tag_redraw(context)
        return (f"Preview Matches: {len(match.region_pairs)} region pairs, "
                f"{len(pairs)} point pairs" + (f", {len(pins)} pins kept" if pins else ""))


def add_pair(matches, vertex_a, vertex_b, score, pin=False):
    item = matches.pairs.add()
    item.vertex_a, item.vertex_b, item.score, item.pin = vertex_a, vertex_b, score, pin
    return item


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


class PARAMORPH_OT_add_pin(bpy.types.Operator):
    """Pin the selected vertex of the source to the selected vertex of the target: the
    morph takes one to the other (edit both objects, one vertex selected on each)"""
    bl_idname = "paramorph.add_pin"
    bl_label = "Add Pin"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return _poll_two(context)

    def execute(self, context):
        try:
            source, target = two_objects(context)
            a, b = _selected_vertex(context, source), _selected_vertex(context, target)
        except UserError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        matches = context.scene.paramorph_matches
        if stored_matches(context, source, target) is None:  # a new pair of objects
            matches.pairs.clear()
            matches.source, matches.target = source, target
            matches.source_vertices = len(source.data.vertices)
            matches.target_vertices = len(target.data.vertices)
        for i in reversed(range(len(matches.pairs))):  # a pin replaces pairs on its vertices
            if matches.pairs[i].vertex_a == a or matches.pairs[i].vertex_b == b:
                matches.pairs.remove(i)
        add_pair(matches, a, b, 0.0, pin=True)
        matches.pair_index = len(matches.pairs) - 1
        overlay.tag_redraw(context)
        self.report({"INFO"}, f"pinned {source.name} vertex {a} to {target.name} vertex {b}")
        return {"FINISHED"}


class PARAMORPH_OT_remove_pair(bpy.types.Operator):
    """Remove the chosen pair from the matches (the morph will not use it)"""
    bl_idname = "paramorph.remove_pair"
    bl_label = "Remove Pair"
    bl_options = {"REGISTER", "UNDO"}

    index: bpy.props.IntProperty(name="Pair", default=-1, min=-1,
                                 description="Pair to remove (-1: the one chosen in the list)")

    @classmethod
    def poll(cls, context):
        return len(context.scene.paramorph_matches.pairs) > 0

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


class PARAMORPH_OT_clear_matches(bpy.types.Operator):
    """Forget the previewed pairs and pins"""
    bl_idname = "paramorph.clear_matches"
    bl_label = "Clear Matches"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        matches = context.scene.paramorph_matches
        matches.pairs.clear()
        matches.source = matches.target = None
        overlay.tag_redraw(context)
        return {"FINISHED"}


class PARAMORPH_OT_morph_to(_TwoMeshes, bpy.types.Operator):
    """Morph the selected mesh into the active one: a new object on a merged topology with
    shape keys from the source's shape to the target's, keyframed over a frame range"""
    bl_idname = "paramorph.morph_to"
    bl_label = "Morph To"
    bl_options = {"REGISTER", "UNDO"}

    frame_start: bpy.props.IntProperty(name="Start Frame", default=1, description="Frame where the morph starts")
    frame_end: bpy.props.IntProperty(name="End Frame", default=48, description="Frame where it reaches the target")
    in_betweens: bpy.props.IntProperty(
        name="In-Betweens", default=0, min=0, max=16,
        description="Shape keys between source and target (evenly spaced, each keyframed "
                    "at full weight at its time) to sculpt the way")
    easing: bpy.props.EnumProperty(
        name="Timing", default="EASE",
        items=(("LINEAR", "Linear", "Constant speed"),
               ("EASE", "Eased", "Start and end slowly (Bezier)")))
    use_features: bpy.props.BoolProperty(
        name="Match Features", default=True,
        description="Match feature regions and points automatically so alike parts morph "
                    "into each other (off: correspondence by direction from the centre)")
    use_preview: bpy.props.BoolProperty(
        name="Use Previewed Pairs", default=True,
        description="Use the pairs and pins of Preview Matches for these two objects, as edited")
    placement: bpy.props.EnumProperty(
        name="End At", default="SOURCE",
        items=(("SOURCE", "Source's Place", "The target's shape, in the source's place"),
               ("TARGET", "Target's Place", "The morph ends where the target object is")))
    epsilon: bpy.props.FloatProperty(
        name="Face Floor", default=0.05, min=1e-4, max=0.5, subtype="FACTOR",
        description="Smallest face area on the optimized sphere maps, as a share of the mean "
                    "(larger keeps thin parts from collapsing, smaller follows the shape closer)")

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
        VA, FA, tri_poly, tri_loops = _arrays(context, source)
        VB, FB, _, _ = _arrays(context, target)
        options = {"features": self.use_features, "epsilon": self.epsilon}
        # The source's start is native.morph's own choice (the conformal map,
        # or the relaxed radial projection where that squeezes long parts),
        # so a cached conformal map is only reused for the target.
        cached = sphere_cache.get(sphere_cache.key(VB, FB, "conformal"))
        if cached is not None:  # Sphere Map just ran on the target's geometry
            options["sphere_b"] = cached
        matches = stored_matches(context, source, target) if self.use_preview else None
        if matches is not None:
            pairs = np.array([(p.vertex_a, p.vertex_b) for p in matches.pairs if not p.pin], dtype=np.int32)
            pins = np.array([(p.vertex_a, p.vertex_b) for p in matches.pairs if p.pin], dtype=np.int32)
            options["pairs"] = pairs.reshape(-1, 2)
            options["pins"] = pins.reshape(-1, 2)
        state = {"source": source.name, "target": target.name, "arrays_source": (VA, FA),
                 "arrays_target": (VB, FB), "tri_poly": tri_poly, "tri_loops": tri_loops,
                 "previewed": matches is not None}
        return native.morph, (VA, FA, VB, FB), options, state

    def finish(self, context, result, state):
        source, target = bpy.data.objects[state["source"]], bpy.data.objects[state["target"]]
        target_positions = np.asarray(result.target)
        if self.placement == "TARGET":
            to_source = np.array(source.matrix_world.inverted() @ target.matrix_world)
            target_positions = target_positions @ to_source[:3, :3].T + to_source[:3, 3]
        obj = morph_object.build(
            context, f"{source.name} to {target.name}", source, result, target_positions,
            tri_poly=state["tri_poly"], tri_loops=state["tri_loops"], target_name=target.name,
            in_betweens=self.in_betweens, frame_start=self.frame_start, frame_end=self.frame_end,
            easing=self.easing == "EASE")
        for other in context.view_layer.objects:  # objects, not mesh elements
            other.select_set(other == obj)
        context.view_layer.objects.active = obj
        pins = int(np.count_nonzero(np.asarray(result.pair_is_pin)))
        seconds = sum(t for _, t in result.timings)
        return (f"Morph To: {obj.name}, {len(result.faces)} faces, {len(result.pairs) - pins} "
                f"feature pairs{f' + {pins} pins' if pins else ''}, {seconds:.1f} s")


classes = (PARAMORPH_OT_preview_matches, PARAMORPH_OT_add_pin, PARAMORPH_OT_remove_pair,
           PARAMORPH_OT_clear_matches, PARAMORPH_OT_morph_to)
