"""A campaign with the user's controller: a factory that fails is one line before any run with
nothing left behind; a controller that calls ``sys.exit`` on a Dask worker stops that run only;
one that kills its worker process is recorded as that run's failure and the campaign goes on.
"""

import sys
from pathlib import Path

import pytest

from hosedrogue import cli
from hosedrogue.errors import ParameterError
from hosedrogue.studies import executor
from hosedrogue.studies.campaign import run_campaign

sys.path.insert(0, str(Path(__file__).parents[1] / "simulation"))
from test_user_code_faults import USER, scenario_text  # noqa: E402

# the command's process has Python's default SIGINT handler (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("default_sigint")

TURBULENCE = "[turbulence]\nenabled = true\nstart_s = 0.0\nduration_s = 0.2\n"


@pytest.fixture(scope="module")
def user_case(tmp_path_factory):
    """Write the faulty controller's module (importable here and, through PYTHONPATH, on the
    workers of the module's cluster) and return a function writing a 0.2 s turbulent scenario with
    it as the drogue's."""
    folder = tmp_path_factory.mktemp("user")
    (folder / "faulty_user.py").write_text(USER)
    with pytest.MonkeyPatch.context() as mp:
        mp.syspath_prepend(str(folder))
        mp.setenv("PYTHONPATH", f"{folder}:{Path(executor.__file__).parents[2]}")

        def write(fault, when, in_factory=False):
            path = folder / f"{fault}-{when}-{in_factory}.toml"
            text = scenario_text("fixed-rigid", "drogue", fault, when, in_factory)
            path.write_text(text.replace("[hose]", TURBULENCE + "[hose]", 1))
            return str(path)
        yield write
    sys.modules.pop("faulty_user", None)


@pytest.mark.parametrize("fault", ["error", "exit0", "keyboard"])
def test_a_factory_that_fails_is_one_line_before_any_run(user_case, tmp_path, capsys, fault):
    out = tmp_path / "out"
    code = cli.main(["montecarlo", user_case(fault, "t0", in_factory=True), "--runs", "3", "--out", str(out),
                     "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err and "the factory 'faulty_user:factory' raised" in err, err
    assert not out.exists()


@pytest.fixture(scope="module")
def cluster(user_case):
    pytest.importorskip("distributed")
    cluster, client = executor.local_cluster(1)
    yield client
    client.close()
    cluster.close()


@pytest.mark.dask
def test_sys_exit_on_a_worker_stops_that_run_only(user_case, tmp_path, cluster):
    summary = run_campaign(user_case("exit5", "later"), 3, tmp_path / "out", client=cluster,
                           compare_controller=True, progress=False)
    runs = summary.runs
    mine = runs[runs.controller == "python"]
    assert not mine["completed"].any() and (mine["t_end_s"] == 0.05).all()
    assert mine["message"].str.contains("raised SystemExit: 5").all()
    assert runs[runs.controller == "none"]["completed"].all()


@pytest.mark.dask
def test_a_controller_that_kills_its_worker_is_that_run_s_failure(user_case, tmp_path, cluster):
    summary = run_campaign(user_case("kill", "later"), 2, tmp_path / "out", client=cluster, compare_controller=True,
                           progress=False)
    runs = summary.runs
    mine = runs[runs.controller == "python"]
    assert len(mine) == 2 and not mine["completed"].any()
    assert mine["message"].str.contains("died on every try").all()
    # the campaign went on: the same seeds without the controller ran to the end
    assert len(runs[runs.controller == "none"]) == 2 and runs[runs.controller == "none"]["completed"].all()
    # resuming finds every run done: a lost run is a recorded failure, not a hole
    again = run_campaign(user_case("kill", "later"), 2, tmp_path / "out", client=cluster, compare_controller=True,
                         progress=False)
    assert again.new_runs == 0


def test_a_failing_factory_in_python_is_a_parameter_error(user_case, tmp_path):
    with pytest.raises(ParameterError, match="raised SystemExit"):
        run_campaign(user_case("exit0", "t0", in_factory=True), 2, tmp_path / "out", scheduler="synchronous",
                     progress=False)
    assert not (tmp_path / "out").exists()
