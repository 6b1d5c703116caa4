"""Sphinx directive ``readme-examples``: run the README's examples while the docs are built.

Every fenced ``python`` block is executed (in one namespace, in a temporary folder) and every
``$ hosedrogue ...`` line of a shell block is run through :func:`hosedrogue.cli.main`; the page
shows each piece of code followed by what it printed. An exception or a non-zero exit status is a
build error, so the README's examples cannot rot unnoticed.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import shlex
import tempfile
import traceback
from pathlib import Path

from docutils import nodes
from sphinx.util.docutils import SphinxDirective

#: A fenced code block: language (maybe empty) and body.
FENCE = re.compile(r"^```([\w-]*)[^\n]*\n(.*?)^```", re.S | re.M)


@contextlib.contextmanager
def _inside(folder: str):
    old = os.getcwd()
    os.chdir(folder)
    try:
        yield
    finally:
        os.chdir(old)


def _block(text: str, language: str) -> nodes.literal_block:
    node = nodes.literal_block(text, text)
    node["language"] = language
    return node


class ReadmeExamples(SphinxDirective):
    """``.. readme-examples:: PATH``: PATH relative to the current document."""

    required_arguments = 1

    def run(self):
        from hosedrogue.cli import main

        source = (Path(self.env.doc2path(self.env.docname)).parent / self.arguments[0]).resolve()
        self.env.note_dependency(str(source))
        result: list[nodes.Node] = []
        namespace: dict = {"__name__": "__readme__"}
        with tempfile.TemporaryDirectory(prefix="hosedrogue-docs-") as tmp, _inside(tmp):
            for language, code in FENCE.findall(source.read_text(encoding="utf-8")):
                if language == "python":
                    out = io.StringIO()
                    try:
                        with contextlib.redirect_stdout(out):
                            exec(compile(code, f"{source.name} (python example)", "exec"), namespace)
                    except Exception:
                        raise self.error(f"README example failed:\n{traceback.format_exc()}")
                    result.append(_block(code, "python"))
                    result.append(_block(out.getvalue() or "(no output)", "text"))
                    continue
                commands = [line[2:] for line in code.splitlines() if line.startswith("$ hosedrogue ")]
                for command in commands:
                    out = io.StringIO()
                    with contextlib.redirect_stdout(out):
                        status = main(shlex.split(command)[1:])
                    if status != 0:
                        raise self.error(f"README example '{command}' exited with status {status}")
                    result.append(_block(f"$ {command}\n{out.getvalue()}", "text"))
        return result


def setup(app):
    """Register the directive (Sphinx extension entry point).

    Parameters
    ----------
    app : sphinx.application.Sphinx
        The application.
    """
    app.add_directive("readme-examples", ReadmeExamples)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
