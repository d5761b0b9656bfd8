# SPDX-License-Identifier: GPL-3.0-or-later
"""Enabling and disabling the extension leaves nothing behind and raises nothing."""

import sys

import pytest

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


@pytest.mark.slow
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


def test_every_handler_is_registered_in_its_order_relink_last(extension):
    """Each room's HANDLERS list, chained by addon/__init__.py, is what Blender holds, in
    that order; on each event the lighting room's relink runs after every other handler of
    the extension (a relink frees data blocks that their depsgraph updates still name); the
    upward calls are set; disabling removes every handler and clears the calls."""
    import addon_utils
    bpy = be.import_bpy()
    from phong_nodes import addon  # noqa: PLC0415
    from phong_nodes.addon.lighting import forwarding, sync  # noqa: PLC0415
    from phong_nodes.addon.shading import modes  # noqa: PLC0415

    def ours(event):
        mine = {id(f) for e, f in addon.HANDLERS if e == event}
        return [f for f in getattr(bpy.app.handlers, event) if id(f) in mine]

    events = {e for e, _f in addon.HANDLERS}
    assert {"depsgraph_update_post", "load_post", "save_pre", "render_pre"} <= events
    for event in events:
        assert ours(event) == [f for e, f in addon.HANDLERS if e == event], event
    for relink in sync.RELINKS:
        event = next(e for e, f in addon.HANDLERS if f is relink)
        assert ours(event)[-1] is relink, f"{relink.__name__} runs last on {event}"
    # every persistent function of the add-on is in the list (none registered elsewhere)
    package = addon.__name__ + "."
    persistent = {f for name, module in list(sys.modules.items()) if name.startswith(package)
                  for f in vars(module).values()
                  if callable(f) and hasattr(f, "_bpy_persistent")
                  and f.__module__.startswith(package)}
    assert persistent == {f for _e, f in addon.HANDLERS}
    assert modes.refresh in sync.AFTER_FINISH and forwarding._on_model_change() is \
        sync.relink_scene
    addon_utils.disable(be.EXT_MODULE, default_set=True, handle_error=_raise)
    try:
        assert all(ours(event) == [] for event in events)
        assert modes.refresh not in sync.AFTER_FINISH and forwarding._on_model_change is None
    finally:
        addon_utils.enable(be.EXT_MODULE, default_set=True, handle_error=_raise)
    assert be.addon_enabled()
