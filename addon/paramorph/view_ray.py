"""The view ray through the mouse, in an object's own coordinates (what
ray casts against its mesh or a BVH of it need)."""
from bpy_extras import view3d_utils


def mouse_ray(context, obj, event):
    """(origin, unit direction) as mathutils Vectors in obj's coordinates, or
    None outside a 3D view region."""
    region, rv3d = context.region, context.region_data
    if region is None or rv3d is None:
        return None
    coord = (event.mouse_region_x, event.mouse_region_y)
    origin = view3d_utils.region_2d_to_origin_3d(region, rv3d, coord)
    direction = view3d_utils.region_2d_to_vector_3d(region, rv3d, coord)
    to_local = obj.matrix_world.inverted()
    return to_local @ origin, (to_local.to_3x3() @ direction).normalized()
