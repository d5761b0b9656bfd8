# SPDX-License-Identifier: GPL-3.0-or-later
"""What the File ▸ Import / Export operators of the interchange formats share (COLLADA, X3D /
VRML97, FBX's drop): the reports of an import and an export, the check of an export path, the
invoke of a file dropped on the 3D Viewport, and its drop handler."""

import os

import bpy
from bpy.props import StringProperty
from bpy_extras.io_utils import ImportHelper


def run_import(operator, label: str, path: str, read, error_type) -> set:
    """Call *read()* -> (objects, materials, warnings, ...) and report as *label* ("Import
    X3D"): the file's problem (*error_type*, whose message names the file) as an error, each
    warning, and what was made."""
    try:
        objects, made, warnings, *_rest = read()
    except error_type as error:
        operator.report({"ERROR"}, f"{label}: {error}")
        return {"CANCELLED"}
    for warning in warnings:
        operator.report({"WARNING"}, f"{label}: {warning}")
    operator.report({"INFO"}, f"Imported {len(objects)} object(s) with {len(made)} Phong "
                              f"material(s) from {os.path.basename(path)}")
    return {"FINISHED"}


def run_export(operator, label: str, path: str, write) -> set:
    """Call *write()* -> warnings when *path* is a file in an existing folder, and report as
    *label* ("Export COLLADA"): a path or write error, each warning, the file written."""
    if not path or os.path.isdir(path) or not os.path.isdir(os.path.dirname(path) or "."):
        operator.report({"ERROR"}, f"{label}: {path!r} is not a file in an existing folder")
        return {"CANCELLED"}
    try:
        warnings = write()
    except (OSError, ValueError) as error:
        operator.report({"ERROR"}, f"{label}: cannot write {path}: {error}")
        return {"CANCELLED"}
    for warning in warnings:
        operator.report({"WARNING"}, f"{label}: {warning}")
    operator.report({"INFO"}, f"Wrote {path}")
    return {"FINISHED"}


class DroppableImport(ImportHelper):
    """The shared part of the import operators that take a file dropped on the 3D Viewport
    (COLLADA, X3D / VRML97, FBX): undoable, the path not remembered between runs (a path set
    before invoke is a dropped file, imported at once: :func:`invoke_import`)."""

    bl_options = {"REGISTER", "UNDO"}
    filepath: StringProperty(subtype="FILE_PATH", options={"SKIP_SAVE"})

    def invoke(self, context, event):
        return invoke_import(self, context, event)


def invoke_import(operator, context, event) -> set:
    """An import operator's invoke: a path set before invoke is a file dropped on the viewport
    (the drop handler), imported at once; otherwise the file browser."""
    if operator.filepath:
        return operator.execute(context)
    return ImportHelper.invoke(operator, context, event)


def drop_handler(idname: str, label: str, operator: str, extensions) -> list:
    """[a FileHandler class] that imports files of *extensions* dropped on the 3D Viewport with
    *operator*, or [] where the release has no ``bpy.types.FileHandler``."""
    if not hasattr(bpy.types, "FileHandler"):
        return []

    def poll_drop(cls, context):
        return context.area is not None and context.area.type == "VIEW_3D"

    return [type(idname, (bpy.types.FileHandler,), {
        "bl_idname": idname, "bl_label": label, "bl_import_operator": operator,
        "bl_file_extensions": ";".join(extensions), "poll_drop": classmethod(poll_drop)})]
