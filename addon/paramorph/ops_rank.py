"""Rank Similar Shapes (thesis 3.5.3): the scene's mesh objects listed by how
close their shape signature (histogram of the area stretch of a conformal
sphere map) is to the active object's. The list shows in the panel."""
import bpy
import numpy as np

from . import bridge, repair_mesh, sphere_cache
from .native import native
from .native_operator import NativeOperator, UserError
from .preferences import backend

_signature_cache = {}  # sphere_cache.key(V, F) -> signature


class ParamorphSimilarShape(bpy.types.PropertyGroup):
    object_name: bpy.props.StringProperty(name="Object")
    distance: bpy.props.FloatProperty(name="Distance", default=-1.0,
                                      description="Signature distance (0: the same shape); -1: not comparable")
    note: bpy.props.StringProperty(name="Note", description="Why the object could not be compared")


def _signatures(items, *, progress, backend, repair=False):
    """Signatures of (name, key, V, F) items (each mended first when
    `repair`); an exception per item that fails."""
    out = []
    for i, (name, key, V, F) in enumerate(items):
        key = key + ("repaired",) if repair else key
        if key in _signature_cache:
            out.append((name, _signature_cache[key]))
            continue

        def item_progress(fraction, stage, i=i):
            return progress((i + fraction) / len(items), f"{name}: {stage}")
        try:
            if repair:
                fixed = repair_mesh.repair(V, F, item_progress)
                V, F = fixed.V, fixed.F
                item_progress = repair_mesh.after_repair(item_progress)
            sphere = sphere_cache.get(sphere_cache.key(V, F))
            if sphere is None:
                sphere = native.sphere_map(V, F, backend=backend, progress=item_progress).positions
            signature = native.shape_signature(V, F, sphere=sphere)
            _signature_cache[key] = signature
            out.append((name, signature))
        except native.Cancelled:
            raise
        except Exception as error:  # listed with its reason, not fatal for the ranking
            out.append((name, error))
    return out


class PARAMORPH_OT_rank_similar_shapes(NativeOperator, bpy.types.Operator):
    """List the scene's mesh objects by how similar their shape is to the active
    object's (area-stretch signatures of conformal sphere maps)"""
    bl_idname = "paramorph.rank_similar_shapes"
    bl_label = "Rank Similar Shapes"
    # UNDO as well: Blender shows the redo panel (Repair, Apply Modifiers) only
    # for operators with both; what it writes is the scene's list.
    bl_options = {"REGISTER", "UNDO"}

    repair: repair_mesh.REPAIR_PROPERTY
    apply_modifiers: bpy.props.BoolProperty(
        name="Apply Modifiers", default=True,
        description="Compare the shapes as the viewport shows them, modifiers included (e.g. a "
                    "Subdivision Surface's smooth shape); off: their meshes without modifiers")

    def prepare(self, context):
        active = context.active_object
        others = [o for o in context.scene.objects if o.type == "MESH" and o != active]
        if not others:
            raise UserError("add other mesh objects to the scene to compare the active one with")
        items = []
        for obj in [active] + others:  # a handful of objects, not mesh elements
            with bridge.object_mode(context, obj):
                V, F = (bridge.evaluated_arrays(context, obj) if self.apply_modifiers
                        else bridge.mesh_arrays(obj.data)[:2])
            V = bridge.as_placed(V, obj)
            items.append((obj.name, sphere_cache.key(V, F), V, F))
        state = {"active": active.name, "arrays": (items[0][2], items[0][3]),
                 "faces": sum(len(item[3]) for item in items),
                 "objects": [] if self.apply_modifiers else [obj.name for obj in [active] + others]}
        return _signatures, (items,), {"backend": backend(context), "repair": self.repair}, state

    def finish(self, context, result, state):
        reference = result[0][1]
        ranking = []
        for name, signature in result[1:]:
            if isinstance(signature, Exception):
                ranking.append((np.inf, name, type(signature).__name__ + ": " + str(signature)))
            else:
                ranking.append((native.signature_distance(reference, signature), name, ""))
        ranking.sort(key=lambda r: (r[0], r[1]))
        listing = context.scene.paramorph_similar
        listing.clear()
        for distance, name, note in ranking:
            item = listing.add()
            item.object_name, item.note = name, note
            item.distance = distance if np.isfinite(distance) else -1.0
        context.scene.paramorph.similar_reference = state["active"]
        best = ranking[0]
        return (f"Rank Similar Shapes: {len(ranking)} objects; closest to {state['active']} is "
                f"{best[1]}" + (f" ({best[0]:.3f})" if np.isfinite(best[0]) else ""))

    def _finish(self, context, job, state):
        # A failure of the reference object's own map is reported like any native error.
        if job.error is None and isinstance(job.result[0][1], Exception):
            job.error, job.result = job.result[0][1], None
        return super()._finish(context, job, state)


classes = (ParamorphSimilarShape, PARAMORPH_OT_rank_similar_shapes)


def register():
    bpy.types.Scene.paramorph_similar = bpy.props.CollectionProperty(type=ParamorphSimilarShape)


def unregister():
    del bpy.types.Scene.paramorph_similar
