"""The interactive viewer: any run's hose, drogue, tow point and probe in 3D with their time
series, in one self-contained HTML file (``hosedrogue view``; docs/viewer.md).

* :func:`read_run` - a run's folder (``timeseries.csv``, ``run.json``, ``hose.npz``) as a
  :class:`ViewRun`; :meth:`ViewRun.from_result` - the same from a result in memory;
* :func:`write_view` / :func:`view_html` - the page of one or more runs (overlaid or side by
  side), its 3D library (three.js) and chart library (uPlot) bundled inside it with their
  licences, so it opens from a file with no network.

Quick start::

    import hosedrogue as hd
    from hosedrogue import viewer

    result = hd.run(hd.load_scenario("engage-locked"))
    viewer.write_view([viewer.ViewRun.from_result(result)], "out/engage-locked.html")
"""

from .page import LAYOUTS, view_html, write_view
from .runs import RUN_FILES, ViewRun, read_run

__all__ = ["ViewRun", "read_run", "view_html", "write_view", "LAYOUTS", "RUN_FILES"]
