"""Sphere Map operator (thesis ch. 3): UV layer "Sphere" from spherical
coordinates, shape key "Sphere"."""
import bpy

from . import bridge, sphere_cache
from .native import native
from .native_operator import NativeOperator
from .preferences import backend


class PARAMORPH_OT_sphere_map(NativeOperator, bpy.types.Operator):
    """Map the active closed genus-0 mesh onto the sphere without folds: writes the
    "Sphere" UV layer and the "Sphere" shape key"""
    bl_idname = "paramorph.sphere_map"
    bl_label = "Sphere Map"
    bl_options = {"REGISTER", "UNDO"}

    weights: bpy.props.EnumProperty(
        name="Weights",
        items=[("conformal", "Conformal", "Cotangent weights: angles kept, best for texturing"),
               ("barycentric", "Barycentric", "Uniform weights: robust on poor triangles")],
        default="conformal")
    shape_key: bpy.props.BoolProperty(
        name="Shape Key", default=True, description="Also add the \"Sphere\" shape key")

    def prepare(self, context):
        obj = context.active_object
        with bridge.object_mode(context, obj):  # Edit Mode keeps the data in a BMesh
            V, F, _, _ = bridge.mesh_arrays(obj.data)
        state = {"arrays": (V, F), "object": obj.name,
                 "cache_key": sphere_cache.key(V, F, self.weights)}
        return native.sphere_map, (V, F), {"weights": self.weights, "backend": backend(context)}, state

    def finish(self, context, result, state):
        sphere_cache.put(state["cache_key"], result.positions)
        obj = bpy.data.objects[state["object"]]
        with bridge.object_mode(context, obj):
            bridge.write_sphere_map(obj, state["arrays"][0], result, shape_key=self.shape_key)
        return (f"Sphere map: {len(result.positions)} vertices, {result.flipped} folds, "
                f"{result.seconds:.2f} s on {result.backend}")


classes = (PARAMORPH_OT_sphere_map,)
