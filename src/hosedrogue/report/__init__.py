"""The reproduction report: every result of Wu et al. (2018) Sec. 2.3 and 3 regenerated from this
project's model, and the engagement and docking studies beyond it, written as one self-contained
HTML page with its figures (PNG), the data behind every figure and table (CSV), the headline
numbers (``report.json``) and animations (GIF).

The report presents: the computations are library calls (``analysis``, ``controllers``,
``studies``, ...). Its files are written through :class:`.writer.ReportFolder`, but for the GIFs
(:mod:`hosedrogue.plotting`) and the docking campaigns' folders
(:func:`hosedrogue.studies.docking.run_grid`), which are written into it. Nothing here tunes anything to the
paper: the paper's numbers (:mod:`hosedrogue.spec.paper`) are shown beside this project's, with their
ratio and a plain explanation of each large difference.

Layout
------
- :mod:`.plan`: the ordered list of sections (``SECTIONS``, then ``CLOSING``), what each needs,
  which a partial build (``--only``) runs;
- :mod:`.build`: :func:`build_report`, in one process or, independent sections side by side, in
  several (:mod:`.parallel`: each process returns what its sections added, merged in build
  order, so the report is the same);
- :mod:`.settings`: every difference between the full and the fast version (``FULL``, ``FAST``);
- :mod:`.writer`: the output folder (CSV, PNG, JSON, page fragments, summary, headline numbers);
- :mod:`.markup`: number formatting and HTML tables and figures;
- :mod:`.comparison`: the paper-vs-ours rows the sections add (``CLOSE``), and
  :mod:`.paper_table`, the closing section that writes them;
- :mod:`.section_results`: section results read by more than one module;
- :mod:`.page`: page assembly and CSS;
- :mod:`.runs`: the nonlinear runs and their window statistics;
- one module per section: :mod:`.parameters`, :mod:`.convergence`, :mod:`.accuracy`, :mod:`.sweep`,
  :mod:`.turbulence_speeds`, :mod:`.linear` (+ :mod:`.linear_responses`), :mod:`.controllers`,
  :mod:`.closed_loop`, :mod:`.hose_views`, :mod:`.long_runs`, :mod:`.engagement`
  (beyond the paper: the refuelling engagement), :mod:`.docking` (beyond the paper: docking
  statistics and the bow wave, with :mod:`.docking_speed`, :mod:`.docking_force` and
  :mod:`.docking_cells`), :mod:`.differences`.

Each section module has a ``build(out, settings, **needs)`` function that computes (library
calls), then writes its CSV files, then its figures (functions of :mod:`hosedrogue.plotting`),
then its HTML section, and returns a small frozen dataclass for later sections (or None).

Adding a section
----------------
1. Write ``report/<name>.py`` with ``build(out, settings, *, <needed keys>) -> Result | None``;
   inside it call ``out.csv``, ``out.figure``, ``out.section(anchor, nav_name, html)`` and, if
   wanted, ``out.summarize(text)``, ``out.comparison.add(...)`` and ``out.record(key, numbers)``.
   Read published numbers from :mod:`hosedrogue.spec.paper`.
2. Add one line to ``SECTIONS`` in :mod:`.plan`, e.g.
   ``Section("lqr", "LQR", lqr.build, needs=("linear",))``, at its place in the order (the page
   shows sections in build order, after ``page.FRONT``), and import the module there. Its result
   must pickle if a later section needs it (it may be built in another process).
"""

from .build import FAST, FULL, ReportSettings, build_report

__all__ = ["build_report", "ReportSettings", "FULL", "FAST"]
