"""Paramorph: fold-free parameterization, feature-aware morphing and feature
cut-and-paste for Blender. The C++ core is the `paramorph_native` module;
`bridge` moves mesh data between Blender and numpy."""

bl_info = {
    "name": "Paramorph",
    "author": "paramorph developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "3D View > Sidebar > Paramorph",
    "description": "Fold-free sphere maps and parameterizations (native core)",
    "category": "Mesh",
}


def register():
    # Operators and panels are registered here as they land; importing the
    # native module lazily keeps the add-on loadable without it.
    from . import native  # noqa: F401


def unregister():
    pass
