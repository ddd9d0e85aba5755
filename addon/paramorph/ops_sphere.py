"""Sphere Map operator (thesis ch. 3): UV layer "Sphere" from spherical
coordinates, shape key "Sphere"."""
import bpy
import numpy as np

from . import bridge, repair_mesh, sphere_cache
from .native import native
from .native_operator import NativeOperator
from .preferences import backend


class PARAMORPH_OT_sphere_map(NativeOperator, bpy.types.Operator):
    """Map the active mesh onto a sphere without folds (a closed, sphere-like surface; Repair
    mends one that is not): writes the "Sphere" UV layer and the "Sphere" shape key"""
    bl_idname = "paramorph.sphere_map"
    bl_label = "Sphere Map"
    bl_options = {"REGISTER", "UNDO"}

    weights: bpy.props.EnumProperty(
        name="Weights",
        items=[("conformal", "Keep Angles", "Shapes of small details kept, best for texturing (conformal, "
                "cotangent weights)"),
               ("barycentric", "Even Spread", "Robust on long thin triangles (barycentric, uniform weights)")],
        default="conformal")
    shape_key: bpy.props.BoolProperty(
        name="Shape Key", default=True, description="Also add the \"Sphere\" shape key")
    repair: repair_mesh.REPAIR_PROPERTY

    def prepare(self, context):
        obj = context.active_object
        with bridge.object_mode(context, obj):  # Edit Mode keeps the data in a BMesh
            V, F, _, _ = bridge.mesh_arrays(obj.data)
        state = {"arrays": (V, F), "object": obj.name, "objects": [obj.name]}
        function = repair_mesh.repaired_call(native.sphere_map) if self.repair else native.sphere_map
        placed = bridge.as_placed(V, obj)
        state["placed"] = placed
        return function, (placed, F), {"weights": self.weights, "backend": backend(context)}, state

    def finish(self, context, result, state):
        V, F = state["arrays"]
        fixed, result = result if self.repair else (None, result)
        computed_on = (fixed.V, fixed.F) if fixed is not None else (state["placed"], F)
        sphere_cache.put(sphere_cache.key(*computed_on, self.weights), result.positions)
        positions, mapped = result.positions, None
        if fixed is not None:
            mapped = fixed.kept_vertices()
            positions = fixed.to_input(result.positions, np.zeros_like(V))
        obj = bpy.data.objects[state["object"]]
        with bridge.object_mode(context, obj):
            bridge.write_sphere_map(obj, V, positions, shape_key=self.shape_key, mapped=mapped)
        line = (f"Sphere map: {len(result.positions)} vertices, {result.flipped} folds, "
                f"{result.seconds:.2f} s on {result.backend}")
        if getattr(result, "initial_map", "") == "progressive":
            # Long limbs: the conformal map would squeeze them to nothing.
            line += " (long parts: laid out coarse to fine, as conformal as they allow)"
        return repair_mesh.with_summary(line, fixed)


classes = (PARAMORPH_OT_sphere_map,)
