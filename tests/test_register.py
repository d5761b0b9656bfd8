# SPDX-License-Identifier: GPL-3.0-or-later
"""Enabling and disabling the extension leaves nothing behind and raises nothing."""

import blender_env as be


def snapshot(bpy):
    handlers = {name: len(getattr(bpy.app.handlers, name)) for name in dir(bpy.app.handlers)
                if isinstance(getattr(bpy.app.handlers, name), list)}
    return {
        "types": sorted(name for name in dir(bpy.types) if "phong" in name.lower()),
        "ops": sorted(dir(bpy.ops.phong)),
        "add_menu": len(bpy.types.NODE_MT_add._dyn_ui_initialize()),
        "handlers": handlers,
        "asset_libraries": sorted(lib.name for lib in
                                  bpy.context.preferences.filepaths.asset_libraries
                                  if "phong" in lib.name.lower()),
        "properties": sorted(
            f"{t.__name__}.{p}" for t in (bpy.types.Light, bpy.types.World, bpy.types.Material,
                                          bpy.types.Object, bpy.types.Scene)
            for p in dir(t) if "phong" in p.lower()),
    }


def test_enable_disable_fifty_times_leaves_nothing_behind(extension):
    import addon_utils
    bpy = be.import_bpy()
    enabled = snapshot(bpy)
    assert enabled["types"] and enabled["ops"], "the extension registers something"
    assert enabled["asset_libraries"] == ["Phong Nodes"]
    addon_utils.disable(be.EXT_MODULE, default_set=True)
    disabled = snapshot(bpy)
    assert disabled["types"] == [] and disabled["ops"] == [] and disabled["properties"] == []
    assert disabled["asset_libraries"] == [], "the asset library leaves the Preferences"
    for _ in range(50):
        addon_utils.enable(be.EXT_MODULE, default_set=True, handle_error=_raise)
        assert snapshot(bpy) == enabled
        addon_utils.disable(be.EXT_MODULE, default_set=True, handle_error=_raise)
        assert snapshot(bpy) == disabled
    addon_utils.enable(be.EXT_MODULE, default_set=True, handle_error=_raise)
    assert be.addon_enabled()


def _raise(error):
    raise error
