"""hose.npz's stacking of the joints: the fixed-length hose's (N, n+1, 3) array and the engagement's
list of per-time arrays give the same file content."""

import numpy as np

from hosedrogue.results.hose_file import split_joints, stack_joints


def test_an_array_of_shapes_stacks_as_the_list_of_its_rows():
    rng = np.random.default_rng(3)
    shapes = rng.normal(size=(7, 5, 3))
    counts, joints = stack_joints(shapes)
    counts_l, joints_l = stack_joints(list(shapes))
    assert counts.dtype == counts_l.dtype == np.int64
    assert np.array_equal(counts, counts_l) and np.array_equal(joints, joints_l)
    assert joints.flags.c_contiguous and joints.shape == (35, 3)
    assert all(np.array_equal(a, b) for a, b in zip(split_joints(counts, joints), shapes))


def test_no_output_time_stacks_to_empty_arrays():
    counts, joints = stack_joints(np.empty((0, 5, 3)))
    assert counts.shape == (0,) and joints.shape == (0, 3)
    counts, joints = stack_joints([])
    assert counts.shape == (0,) and joints.shape == (0, 3)
