# SPDX-License-Identifier: GPL-3.0-or-later
"""One owner for what each lighting model reads of a light (``node_groups/models.py``, each
model's ``settings``): the panel, the rig's drivers and the reference's description all
follow it.  The expected
lists are the contract's (docs/contract.md, docs/threejs.md)."""

import pytest


@pytest.mark.parametrize("model, kind, falloff, expected", [
    ("seeds", "POINT", "QUADRATIC", ["intensity", "falloff", "quadratic", "linear", "constant",
                                     "diffuse", "specular"]),
    ("seeds", "SPOT", "POWER", ["intensity", "falloff", "power_k", "edge_exponent", "diffuse",
                                "specular"]),
    ("seeds", "SUN", "POWER", ["intensity", "diffuse", "specular"]),
    ("threejs", "SPOT", "POWER", ["intensity", "distance", "decay", "penumbra"]),
    ("threejs", "SUN", "QUADRATIC", ["intensity"]),
])
def test_what_each_model_reads_of_a_light(bpy_clean, model, kind, falloff, expected):
    bpy = bpy_clean
    from phong_nodes.addon.lighting import properties  # noqa: PLC0415

    light = bpy.data.lights.new("L", kind)
    light.phong.falloff = falloff
    assert [attr for attr, _target in properties.model_settings(model, light)] == expected


def test_every_driven_input_is_driven_from_its_setting(bpy_clean):
    """The rig drives exactly the light-group inputs the table names, from their custom
    properties: a Spot with Power falloff in the seeds' model has no driver on Quadratic."""
    bpy = bpy_clean
    from phong_nodes.addon.lighting import properties, rig  # noqa: PLC0415

    scene = bpy.context.scene
    light = bpy.data.lights.new("Spot", "SPOT")
    obj = bpy.data.objects.new("Spot", light)
    scene.collection.objects.link(obj)
    light.phong.falloff = "POWER"
    tree = bpy.data.node_groups.new("probe", "ShaderNodeTree")
    rig.build(tree, [obj], scene.world)
    node = tree.nodes[f"light:{obj.name}"]
    driven = {fc.data_path: fc.driver.variables[0].targets[0].data_path
              for fc in tree.animation_data.drivers
              if fc.data_path.startswith(f'nodes["{node.name}"]')}
    by_input = {node.inputs[int(path.split("inputs[")[1].split("]")[0])].name: target
                for path, target in driven.items()}
    assert by_input["Intensity"] == '["phong_intensity"]'
    assert by_input["Edge Exponent"] == '["phong_edge_exponent"]'
    assert "Quadratic" not in by_input and "Linear" not in by_input
    assert by_input["Half Angle"] == "spot_size"
    for attr, target in properties.model_settings("seeds", light):
        if target is not None:
            assert by_input[target] == f'["{properties.LIGHT_KEYS[attr][0]}"]'
