"""Sphinx extension: myst-nb's stream merging must not change the executed notebook.

With ``nb_merge_streams: true`` myst-nb renders a cell's consecutive ``stdout`` (and
``stderr``) outputs as one, through ``myst_nb.core.utils.coalesce_streams``.  That function
(myst-nb 1.x) appends the later outputs' text to the first output *in place*, and the
notebook it was handed is the one written to ``_build/jupyter_execute/<chapter>.ipynb`` (the
notebook a reader downloads): a cell whose two ``print`` calls arrived as two stream
messages (on a loaded machine, seconds apart) is written with the second line twice, once
merged into the first output and once in its own.  The determinism test caught it in CI.

Here the merge works on a copy of the outputs, so the page shows the merged text and the
written notebook keeps the kernel's outputs as they came.
"""

from __future__ import annotations

import copy


def _merge_on_a_copy(app, config) -> None:
    from myst_nb.core import render

    inner = render.coalesce_streams
    if getattr(inner, "gyrolib_copy", False):
        return

    def coalesce_streams(outputs):
        return inner(copy.deepcopy(outputs))

    coalesce_streams.gyrolib_copy = True
    render.coalesce_streams = coalesce_streams


def setup(app):
    app.connect("config-inited", _merge_on_a_copy)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
