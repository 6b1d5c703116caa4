"""The engagement's .mat holds its states (docs/interop.md): ``states`` (N x 4 n_max) [q, qd] with
``state_names``, NaN beyond a row's links, and each link's chart. Checked against the joints of
hose.npz, an independent output of the same run: every link's direction from its two joints is
the direction its angles give, e_k = [-c1 c2, -s2, s1 c2] (docs/model.md), turned by the
alternative chart's rotation (x, y, z) -> (x, -z, y) where the link uses it."""

import numpy as np
from scipy.io import loadmat

from hosedrogue.cli import main
from hosedrogue.results.hose_file import read_hose_npz, split_joints

#: Directions from joints and from angles agree to this [-]: both from the same double-precision
#: state, the joints through a sum of link vectors (rounding ~1e-15 m over ~1 m links).
SAME_DIRECTION = 1e-9


def _directions(q, chart):
    c1, s1, c2, s2 = np.cos(q[0::2]), np.sin(q[0::2]), np.cos(q[1::2]), np.sin(q[1::2])
    e = np.column_stack([-c1 * c2, -s2, s1 * c2])
    alt = chart == 1.0
    e[alt] = np.column_stack([e[alt, 0], -e[alt, 2], e[alt, 1]])
    return e


def test_the_engagement_mat_holds_its_states(tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["simulate", "engage-response", "--duration", "0.3", "--format", "mat", "--out", str(out)]) == 0
    capsys.readouterr()
    m = loadmat(out / "timeseries.mat", squeeze_me=False)
    x, chart = m["states"], m["charts"]
    names = [str(np.asarray(v).ravel()[0]) for v in m["state_names"].ravel()]
    n_max = chart.shape[1]
    assert x.shape == (m["t_s"].shape[0], 4 * n_max) and len(names) == 4 * n_max
    assert names[0] == "theta_1_1_rad" and names[2 * n_max] == "theta_1_1_rad_s"
    links = m["signals"][0, 0]["links"].ravel().astype(int)
    t, counts, joints = read_hose_npz(out / "hose.npz")
    per_time = split_joints(counts, joints)
    for i in range(0, t.size, max(1, t.size // 10)):
        n = links[i]
        assert np.all(np.isfinite(x[i, :2 * n])) and np.all(np.isnan(x[i, 2 * n:2 * n_max]))
        j = per_time[i]
        d = np.diff(j, axis=0)
        d /= np.linalg.norm(d, axis=1)[:, None]
        assert np.allclose(_directions(x[i, :2 * n], chart[i, :n]), d, atol=SAME_DIRECTION, rtol=0.0)
