# SPDX-License-Identifier: GPL-3.0-or-later
"""The lighting models are written once (node_groups/models.py, issue 44): each entry's
groups exist with the inputs it names, no module that differs by model spells a model's
name, and an entry added to the table is a model the Per Vertex / Per Face expression, the
lights group, the settings and the Lighting Model menu know (pure tests, and Blender tests
where the add-on reads the table)."""

from __future__ import annotations

import dataclasses
import io
import os
import tokenize

import pytest

from phong_nodes.node_groups import library, models, shading_modes

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
#: The modules that differ by model and must read the table (the issue's list).
READERS = ("node_groups/shading_modes.py", "addon/lighting/rig.py",
           "addon/lighting/properties.py", "addon/lighting/loop.py", "addon/ui/panels.py",
           "addon/shading/modes.py", "addon/shading/groups.py", "addon/lighting/lights.py",
           # the exporters ask the model for its mapping (core/x3d/phong.py, core/fbx/phong.py)
           "addon/interchange/x3d_export.py", "addon/interchange/fbx_export.py",
           "addon/interchange/threejs_export.py")


def test_the_table_is_sound():
    assert models.check() == []
    assert models.NAMES[0] == "seeds", "a scene without a model is in the seeds' model"
    assert set(models.NAMES) == {"seeds", "threejs", "x3d"}


@pytest.mark.parametrize("name", models.NAMES)
def test_each_models_groups_have_the_inputs_the_table_names(name):
    model = models.MODELS[name]
    for light_type, group in model.light_groups.items():
        inputs = {s.name for s in library.definition(group).inputs}
        for attr, types, _when, target in model.settings:
            if target is not None and light_type in types:
                assert target in inputs, f"{group} has no input {target} ({attr})"
    spot = {s.name for s in library.definition(model.light_groups["SPOT"]).inputs}
    assert model.spot_angle in spot


def test_the_loop_groups_are_the_tables():
    assert {n: m.loop for n, m in models.MODELS.items() if m.loop} == {
        n: spec.group for n, spec in library.LOOP_MODELS.items()}
    for spec in library.LOOP_MODELS.values():
        assert spec.group in library.RIG_GROUPS


def test_every_composition_has_its_expression():
    assert set(shading_modes.COMPOSE) == set(models.COMPOSITIONS)


def _string_literals(path):
    with open(os.path.join(ROOT, path), encoding="utf-8") as handle:
        source = handle.read()
    return [tok.string for tok in tokenize.generate_tokens(io.StringIO(source).readline)
            if tok.type == tokenize.STRING]


@pytest.mark.parametrize("path", [p for p in READERS if os.path.exists(os.path.join(ROOT, p))])
def test_no_reader_spells_a_model(path):
    """Only models.py (and the groups of each model in library.py) name the models: the
    modules that differ by model read the table."""
    names = {repr(n) for n in models.NAMES} | {f'"{n}"' for n in models.NAMES}
    assert not [s for s in _string_literals(path) if s in names]


def _with_a_fourth_model(monkeypatch, like="x3d", name="fourth", prefix="Fourth"):
    fourth = dataclasses.replace(models.MODELS[like], name=name, label="A fourth model",
                                 prefix=prefix)
    monkeypatch.setitem(models.MODELS, name, fourth)
    return fourth


@pytest.mark.parametrize("like", models.NAMES)
def test_a_fourth_model_is_one_table_entry(monkeypatch, like):
    """An entry that composes as *like*, with its light groups: the Per Vertex / Per Face
    expression of it is *like*'s, for every light type."""
    _with_a_fourth_model(monkeypatch, like)
    types = ["POINT", "SUN", "SPOT"]
    assert (shading_modes.model_color(types, "fourth", {0}).key
            == shading_modes.model_color(types, like, {0}).key)
    monkeypatch.delitem(models.MODELS, "fourth")
    with pytest.raises(ValueError):
        shading_modes.model_color(types, "fourth")


def test_the_menu_and_the_lights_group_read_the_table(bpy_clean, monkeypatch):
    """Blender: the Lighting Model menu's items are the table's; a fourth entry gets its
    lights group (its prefix, its light groups, its settings driven) without any other
    change."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import properties, rig  # noqa: PLC0415

    items = bpy.context.scene.phong.bl_rna.properties["model"].enum_items
    assert [i.identifier for i in items] == list(models.NAMES)
    assert set(rig.COMPOSE) == set(models.COMPOSITIONS)
    fourth = _with_a_fourth_model(monkeypatch, "x3d")
    scene = bpy.context.scene
    light = bpy.data.lights.new("Spot", "SPOT")
    obj = bpy.data.objects.new("Spot", light)
    scene.collection.objects.link(obj)
    scene[rig.MODEL_KEY] = "fourth"
    assert rig.model_of(scene) == "fourth"
    assert rig.group_name(scene, [obj], rig.ALL) == f"Fourth Lights {scene.name}"
    assert [a for a, _t in properties.model_settings("fourth", light)] == [
        a for a, _t in properties.model_settings("x3d", light)]
    tree = bpy.data.node_groups.new("probe", "ShaderNodeTree")
    rig.build(tree, [obj], scene.world, "fourth")
    assert tree[rig.MODEL_KEY] == "fourth"
    node = tree.nodes[f"light:{obj.name}"]
    assert node.node_tree.name == f"{fourth.rig} Spot"  # its table entry's lights group part
    driven = {fc.data_path for fc in tree.animation_data.drivers}
    spot = node.inputs[fourth.spot_angle]
    assert spot.path_from_id("default_value") in driven
