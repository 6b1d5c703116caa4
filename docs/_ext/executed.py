"""Sphinx directives that run the documentation's examples while the docs are built.

* ``run-python``: the block's Python is executed (one namespace per page, blocks in page order)
  and the page shows the code, then what it printed; ``:figure: NAME`` also shows the matplotlib
  figure bound to ``NAME`` by the block;
* ``run-shell``: every ``$ hosedrogue ...`` line of the block is run through
  :func:`hosedrogue.cli.main` and shown with what it printed.

An exception or a non-zero exit status is a build error, so the examples cannot rot unnoticed.
Each page runs in its own folder, ``out/docs-run/PAGE/`` (emptied when the page is read), so the
files the examples write stay out of the source tree. Pages with examples are read again on every
build (``executed_pages`` in conf.py): their output comes from the package, which Sphinx does
not track.

The README's examples are checked the same way when the build starts (:func:`check_readme`),
and the output the README shows under a command must be what it prints now; they are not shown
on a page of their own (the getting-started page and the tutorial show the
same commands and calls, run).
"""

from __future__ import annotations

import base64
import contextlib
import io
import os
import re
import shlex
import shutil
import traceback
from pathlib import Path

from docutils import nodes
from docutils.parsers.rst import directives
from sphinx.errors import ExtensionError
from sphinx.util.docutils import SphinxDirective

#: A fenced code block of a Markdown file: language (maybe empty) and body.
FENCE = re.compile(r"^```([\w-]*)[^\n]*\n(.*?)^```", re.S | re.M)

#: Per page: the namespace its ``run-python`` blocks share.
_NAMESPACES: dict[str, dict] = {}


@contextlib.contextmanager
def _inside(folder: Path):
    old = os.getcwd()
    folder.mkdir(parents=True, exist_ok=True)
    os.chdir(folder)
    try:
        yield
    finally:
        os.chdir(old)


def _block(text: str, language: str, output: bool = False) -> nodes.literal_block:
    node = nodes.literal_block(text, text)
    node["language"] = language
    if output:
        node["classes"].append("example-output")
    return node


def run_folder(app, page: str) -> Path:
    """The folder a page's examples run in: ``<hd_run_dir>/<page>``."""
    return Path(app.config.hd_run_dir) / page.replace("/", "-")


def run_commands(text: str, where: str) -> list[tuple[str, str]]:
    """Run every ``$ hosedrogue ...`` line of ``text``; return (command, what it printed) pairs.

    Raises ``RuntimeError`` naming the command when it exits with a non-zero status.
    """
    from hosedrogue.cli import main

    done = []
    for line in text.splitlines():
        if not line.startswith("$ hosedrogue "):
            continue
        command = line[2:]
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            status = main(shlex.split(command)[1:])
        if status != 0:
            raise RuntimeError(f"{where}: '{command}' exited with status {status}")
        done.append((command, out.getvalue()))
    return done


def run_python(code: str, namespace: dict, where: str) -> str:
    """Execute ``code`` in ``namespace``; return what it printed (RuntimeError with the traceback)."""
    out = io.StringIO()
    try:
        with contextlib.redirect_stdout(out):
            exec(compile(code, where, "exec"), namespace)
    except Exception:
        raise RuntimeError(f"{where} failed:\n{traceback.format_exc()}") from None
    return out.getvalue()


def _figure_node(fig, alt: str) -> nodes.raw:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90, bbox_inches="tight")
    import matplotlib.pyplot as plt

    plt.close(fig)
    data = base64.b64encode(buf.getvalue()).decode("ascii")
    html = f'<img class="example-figure" alt="{alt}" src="data:image/png;base64,{data}" style="max-width:100%">'
    return nodes.raw("", html, format="html")


class RunPython(SphinxDirective):
    """``run-python``: execute the block, show the code and its output (``:figure: NAME``)."""

    has_content = True
    option_spec = {"figure": directives.unchanged, "hide-output": directives.flag}

    def run(self):
        page = self.env.docname
        namespace = _NAMESPACES.setdefault(page, {"__name__": "__main__"})
        code = "\n".join(self.content) + "\n"
        where = f"{page} (example at line {self.lineno})"
        with _inside(run_folder(self.env.app, page)):
            try:
                printed = run_python(code, namespace, where)
            except RuntimeError as exc:
                raise self.error(str(exc))
            result: list[nodes.Node] = [_block(code.rstrip("\n"), "python")]
            if printed and "hide-output" not in self.options:
                result.append(_block(printed.rstrip("\n"), "text", output=True))
            name = self.options.get("figure")
            if name:
                if name not in namespace:
                    raise self.error(f"{where}: no figure named {name!r}")
                result.append(_figure_node(namespace[name], alt=f"figure of the example: {name}"))
        return result


class RunShell(SphinxDirective):
    """``run-shell``: run each ``$ hosedrogue ...`` line, show it with its output."""

    has_content = True

    def run(self):
        page = self.env.docname
        where = f"{page} (commands at line {self.lineno})"
        with _inside(run_folder(self.env.app, page)):
            try:
                done = run_commands("\n".join(self.content), where)
            except RuntimeError as exc:
                raise self.error(str(exc))
        text = "\n".join(f"$ {command}\n{printed.rstrip()}".rstrip() for command, printed in done)
        return [_block(text, "text")]


def _fresh_page(app, docname: str, source: list) -> None:
    """A page with examples starts from an empty namespace and an empty run folder."""
    if "{run-python}" in source[0] or "{run-shell}" in source[0]:
        _NAMESPACES.pop(docname, None)
        folder = run_folder(app, docname)
        shutil.rmtree(folder, ignore_errors=True)


def _always_read(app, env, added, changed, removed):
    return [page for page in app.config.executed_pages if page in env.found_docs]


def shown_outputs(text: str) -> dict[str, list[str]]:
    """``{command: the lines shown under it}`` of a shell block (commands shown without output
    map to an empty list)."""
    shown: dict[str, list[str]] = {}
    current = None
    for line in text.splitlines():
        if line.startswith("$ "):
            current = line[2:]
            shown[current] = []
        elif current is not None:
            shown[current].append(line.rstrip())
    return shown


def check_readme(app) -> None:
    """Run the README's Python blocks and ``$ hosedrogue`` lines (``hd_readme``) in
    ``<hd_run_dir>/readme``; a failure, or a command that no longer prints the output the README
    shows under it, stops the build."""
    readme = Path(app.config.hd_readme)
    if not readme.is_file():
        return
    folder = Path(app.config.hd_run_dir) / "readme"
    shutil.rmtree(folder, ignore_errors=True)
    namespace: dict = {"__name__": "__readme__"}
    with _inside(folder):
        try:
            for language, code in FENCE.findall(readme.read_text(encoding="utf-8")):
                if language == "python":
                    run_python(code, namespace, f"{readme.name} (python example)")
                    continue
                expected = shown_outputs(code)
                for command, printed in run_commands(code, readme.name):
                    want = expected.get(command)
                    got = [line.rstrip() for line in printed.rstrip("\n").splitlines()]
                    if want and want != got:
                        raise RuntimeError(f"{readme.name}: '{command}' now prints\n" + "\n".join(got)
                                           + "\nbut the README shows\n" + "\n".join(want))
        except RuntimeError as exc:
            raise ExtensionError(f"README example failed: {exc}") from None


def setup(app):
    """Register the directives and hooks (Sphinx extension entry point).

    Parameters
    ----------
    app : sphinx.application.Sphinx
        The application.
    """
    app.add_config_value("hd_run_dir", "out/docs-run", "env")
    app.add_config_value("hd_readme", "", "env")
    app.add_config_value("executed_pages", [], "env")
    app.add_directive("run-python", RunPython)
    app.add_directive("run-shell", RunShell)
    app.connect("source-read", _fresh_page)
    app.connect("env-get-outdated", _always_read)
    app.connect("builder-inited", check_readme)
    return {"version": "2", "parallel_read_safe": False, "parallel_write_safe": True}
