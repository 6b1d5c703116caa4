"""User code cannot end a run unseen: a controller of any role (drogue, receiver, reel) that raises,
calls ``sys.exit`` or raises ``KeyboardInterrupt`` itself, in ``reset()``, at t = 0 or later, on
every chain (fixed-length and engagement, rigid and elastic links), stops the run with one line
naming it and the time, and what was computed is kept, marked incomplete; the command exits 3
with its files written. A factory that fails is a one-line error (exit 2) before the run.

The user's controllers live in a module written to a temporary folder (``faulty_user``), named by
entry point as a user's would be.
"""

import json
import sys
import textwrap

import pytest

from hosedrogue import cli
from hosedrogue.errors import ParameterError

# the command's process has Python's default SIGINT handler (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("default_sigint")

USER = textwrap.dedent('''
    import os
    import signal
    import sys
    import time

    def fail(fault):
        if fault == "exit0":
            sys.exit(0)
        if fault == "exit5":
            sys.exit(5)
        if fault == "keyboard":
            raise KeyboardInterrupt
        if fault == "kill":
            os._exit(7)
        if fault == "ctrl-c":  # the user pressing Ctrl-C while the controller runs
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(5)
        raise RuntimeError("boom")

    class Faulty:
        def __init__(self, fault, when, command, at_s):
            self.fault, self.when, self.command, self.at_s = fault, when, command, at_s

        def reset(self, m):
            if self.when == "reset":
                fail(self.fault)

        def __call__(self, t, m):
            if self.when == "t0" or (self.when == "later" and t >= self.at_s):
                fail(self.fault)
            return self.command

    def factory(fault="error", when="t0", command=0.0, at_s=0.05, in_factory=False):
        if in_factory:
            fail(fault)
        return Faulty(fault, when, command, at_s)
''')

#: The command each role's Faulty returns until it fails (a valid one: zero force, zero take-up,
#: the probe's own closure speed).
COMMAND = {"drogue": "[0.0, 0.0]", "reel": "0.0", "receiver": "[1.0, 0.0, 0.0]"}
TABLE = {"drogue": "controller", "reel": "reel", "receiver": "receiver"}
ELASTIC = 'axial_stiffness_n = 1.0e6\naxial_damping_n_s = 3000.0\n'


def scenario_text(chain: str, role: str, fault: str, when: str, in_factory: bool = False) -> str:
    """A 0.2 s run of 8 links (rigid or elastic), fixed-length or engaged, with the faulty controller
    in ``role``."""
    table = TABLE[role]
    head = f'[{table}]\n' + ('type = "python"\n' if role == "drogue" else "") + ('law = "python"\n' if role == "reel" else "")
    user = (f'{head}entry = "faulty_user:factory"\nsample_time_s = 0.01\n'
            f'[{table}.options]\nfault = "{fault}"\nwhen = "{when}"\ncommand = {COMMAND[role]}\n'
            f'in_factory = {"true" if in_factory else "false"}\n')
    elastic = chain.endswith("elastic")
    hose = "[hose]\nlinks = 8\n" + (ELASTIC if elastic else "")
    numerics = '[numerics]\nstep_s = 0.005\noutput_every = 2\n' + ('integrator = "sdirk2"\n' if elastic else "")
    engagement = ""
    if chain.startswith("engagement"):
        engagement = ("[probe]\nstandoff_m = 3.0\nclosure_speed_m_s = 1.0\npush_m = 1.0\n"
                      + ("" if role == "reel" else '[reel]\nlaw = "response"\n'))
    return f'[scenario]\nname = "fault"\nduration_s = 0.2\n{hose}{numerics}{engagement}{user}'


@pytest.fixture
def user_module(tmp_path, monkeypatch):
    (tmp_path / "faulty_user.py").write_text(USER)
    monkeypatch.syspath_prepend(str(tmp_path))
    yield tmp_path
    sys.modules.pop("faulty_user", None)


def simulate(tmp_path, text, capsys):
    path = tmp_path / "case.toml"
    path.write_text(text)
    out = tmp_path / "out"
    code = cli.main(["simulate", str(path), "--out", str(out)])
    captured = capsys.readouterr()
    return code, captured, out


def assert_stopped_and_kept(code, captured, out, role, at_least_s=None):
    err_lines = [line for line in captured.err.splitlines() if line.strip()]
    assert code == 3, (code, captured.err)
    assert len(err_lines) == 1 and "Traceback" not in captured.err, captured.err
    assert f"the {role} controller 'faulty_user:factory'" in err_lines[0]
    meta = json.loads((out / "run.json").read_text())
    assert meta["completed"] is False and "faulty_user:factory" in meta["message"]
    lines = (out / "timeseries.csv").read_text().splitlines()
    assert len(lines) >= 2  # header and at least the initial state: what was computed is kept
    if at_least_s is not None:
        assert float(lines[-1].split(",")[0]) >= at_least_s


CHAINS = ["fixed-rigid", "engagement-rigid", "engagement-elastic"]
FAULTS = ["exit0", "exit5", "keyboard", "error"]


@pytest.mark.parametrize("chain", CHAINS)
@pytest.mark.parametrize("fault", FAULTS)
@pytest.mark.parametrize("when", ["reset", "t0", "later"])
def test_a_drogue_controller_that_fails_stops_the_run_in_one_line(user_module, tmp_path, capsys, chain, fault, when):
    code, captured, out = simulate(tmp_path, scenario_text(chain, "drogue", fault, when), capsys)
    # "later" fails at 0.05 s: the samples before it are kept (outputs every 0.01 s)
    assert_stopped_and_kept(code, captured, out, "drogue", 0.04 if when == "later" else None)


@pytest.mark.parametrize("chain", ["engagement-rigid", "engagement-elastic"])
@pytest.mark.parametrize("role", ["receiver", "reel"])
@pytest.mark.parametrize("fault, when", [("exit0", "reset"), ("exit5", "t0"), ("keyboard", "later"),
                                          ("error", "t0")])
def test_a_receiver_or_reel_that_fails_stops_the_run_in_one_line(user_module, tmp_path, capsys, chain, role,
                                                                 fault, when):
    code, captured, out = simulate(tmp_path, scenario_text(chain, role, fault, when), capsys)
    assert_stopped_and_kept(code, captured, out, role)


@pytest.mark.parametrize("role, chain", [("drogue", "fixed-rigid"), ("receiver", "engagement-rigid"),
                                         ("reel", "engagement-elastic")])
@pytest.mark.parametrize("fault", FAULTS)
def test_a_factory_that_fails_is_one_line_before_the_run(user_module, tmp_path, capsys, role, chain, fault):
    code, captured, out = simulate(tmp_path, scenario_text(chain, role, fault, "t0", in_factory=True), capsys)
    err = captured.err.strip()
    assert code == 2 and "\n" not in err and "Traceback" not in err, captured.err
    assert "faulty_user:factory" in err and "raised" in err
    assert not out.exists()


def test_the_python_api_stops_the_run_and_returns_it(user_module, tmp_path):
    from hosedrogue import load_scenario, run

    path = tmp_path / "case.toml"
    path.write_text(scenario_text("engagement-elastic", "drogue", "exit0", "t0"))
    result = run(load_scenario(path))
    assert not result.completed and "raised SystemExit" in result.message
    with pytest.raises(ParameterError, match="raised SystemExit"):
        path.write_text(scenario_text("fixed-rigid", "drogue", "exit5", "t0", in_factory=True))
        run(load_scenario(path))


def test_the_user_s_own_ctrl_c_still_interrupts(user_module, tmp_path, capsys):
    """A real SIGINT while the controller runs is the user's Ctrl-C: the command is interrupted
    (exit 130, one line), not a controller's failure."""
    code, captured, _ = simulate(tmp_path, scenario_text("fixed-rigid", "drogue", "ctrl-c", "later"), capsys)
    assert code == 130 and captured.err.strip() == "hosedrogue: interrupted", captured.err


@pytest.mark.parametrize("chain, role", [("fixed-rigid", "drogue")] + [(c, r) for c in CHAINS[1:]
                                                                         for r in ("drogue", "receiver", "reel")])
def test_the_stop_message_gives_the_time_of_the_last_state_kept(user_module, tmp_path, chain, role):
    """Outputs every 5 steps of 5 ms (0.025 s), a controller failing at its first call from
    0.033 s, i.e. at 0.04 s: the run keeps 0 and 0.025 s, and its message says it stopped at the
    last state kept, 0.025 s (it said 0.04 s: a time the result does not reach), and when the
    controller failed."""
    from hosedrogue import load_scenario, run

    text = scenario_text(chain, role, "error", "later").replace("output_every = 2", "output_every = 5")
    (tmp_path / "case.toml").write_text(text + "at_s = 0.033\n")
    result = run(load_scenario(tmp_path / "case.toml"))
    # the last output time kept: 1e-12 s bounds the round-off of its summed steps (about 1e-17 s)
    assert not result.completed and result.t_s[-1] == pytest.approx(0.025, abs=1e-12)
    assert result.message.startswith("stopped at t = 0.0250 s: ") and "(in its call at t = 0.0400 s)" in result.message
