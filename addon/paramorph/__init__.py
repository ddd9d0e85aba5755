"""Paramorph: fold-free parameterization, feature-aware morphing and feature
cut-and-paste for Blender. The C++ core is the `paramorph_native` module;
`bridge` moves mesh data between Blender and numpy."""

bl_info = {
    "name": "Paramorph",
    "author": "paramorph developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "3D View > Sidebar > Paramorph",
    "description": "Fold-free sphere maps, parameterizations, segmentation, feature-based morphing and feature cut-and-paste (native core)",
    "category": "Mesh",
}


_CLASS_MODULES = ("preferences", "ops_sphere", "ops_unwrap", "ops_segment", "ops_select", "ops_rank",
                  "morph.operators", "morph.pins", "ops_paste", "menus", "panels", "overlay")


def _modules():
    import importlib
    return [importlib.import_module(f".{name}", __package__) for name in _CLASS_MODULES]


def register():
    """Idempotent: a second register (read_homefile, reload) first undoes the first.
    The native module loads lazily inside `native`; without it every class still
    registers and the panel says how to build it."""
    import bpy

    from . import properties
    if hasattr(bpy.types.Scene, "paramorph"):
        unregister()
    properties.register()
    for module in _modules():
        for cls in module.classes:
            bpy.utils.register_class(cls)
        if hasattr(module, "register"):
            module.register()


def unregister():
    import bpy

    from . import properties
    for module in reversed(_modules()):
        if hasattr(module, "unregister"):
            module.unregister()
        for cls in reversed(module.classes):
            if getattr(cls, "is_registered", True):
                try:
                    bpy.utils.unregister_class(cls)
                except RuntimeError:  # never registered (a failed earlier register)
                    pass
    if hasattr(bpy.types.Scene, "paramorph"):
        properties.unregister()
