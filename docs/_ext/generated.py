"""Pages generated from the code when the build starts, so that they cannot drift from it.

* ``cli.md``: every command of ``hosedrogue`` with its purpose and its ``--help``
  (:func:`hosedrogue.cli.build_parser`).

The scenario reference is checked in instead (docs/scenario-reference.md, written by ``hosedrogue
reference --out``; ``tests/package/test_docs.py`` keeps it equal to the code's).

It is written to ``hd_generated_dir`` (under ``out/``, not the source tree) and included by
the page of the same name (``{include}``), which Sphinx then reads again whenever they change.
"""

from __future__ import annotations

import os
from pathlib import Path


def cli_markdown() -> str:
    """Markdown: per sub-command a heading, its one-line purpose and its ``--help`` text."""
    from hosedrogue.cli import build_parser

    old = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = "100"  # argparse wraps its help to the terminal's width
    try:
        parser = build_parser()
        sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
        purposes = {a.dest: a.help for a in sub._choices_actions}
        out = ["## `hosedrogue`", "", "```text", parser.format_help().rstrip(), "```", ""]
        for name, command in sub.choices.items():
            out += [f"## `hosedrogue {name}`", "", _sentence(purposes.get(name) or ""), "",
                    "```text", command.format_help().rstrip(), "```", ""]
    finally:
        if old is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = old
    return "\n".join(out)


def _sentence(text: str) -> str:
    text = text.strip().rstrip(".")
    return (text[:1].upper() + text[1:] + ".") if text else ""


def _write_if_changed(path: Path, text: str) -> None:
    if not path.is_file() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def generate(app) -> None:
    """Write the generated Markdown files (``builder-inited``)."""
    folder = Path(app.config.hd_generated_dir)
    folder.mkdir(parents=True, exist_ok=True)
    _write_if_changed(folder / "cli.md", cli_markdown())


def setup(app):
    """Register the generator (Sphinx extension entry point).

    Parameters
    ----------
    app : sphinx.application.Sphinx
        The application.
    """
    app.add_config_value("hd_generated_dir", "out/docs-generated", "env")
    app.connect("builder-inited", generate)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
