# SPDX-License-Identifier: Apache-2.0
"""numpy ⇄ cv::Mat conversion: every depth, 1–4 channels, strides, ownership, rejections."""
import numpy as np
import pytest

from conftest import make_scene

DEPTHS = {"uint8": 0, "int8": 1, "uint16": 2, "int16": 3, "int32": 4, "float32": 5, "float64": 6, "float16": 7}


@pytest.fixture(scope="module")
def ext(db):
    return db._dynblur


@pytest.mark.parametrize("dtype", list(DEPTHS))
@pytest.mark.parametrize("shape", [(7, 5), (7, 5, 1), (7, 5, 2), (7, 5, 3), (7, 5, 4)])
def test_roundtrip_every_depth_and_channel_count(ext, dtype, shape):
    rng = np.random.default_rng(1)
    a = (rng.random(shape) * 100).astype(dtype)
    info = ext._matInfo(a)
    channels = shape[2] if len(shape) == 3 else 1
    assert info == (7, 5, channels, DEPTHS[dtype])
    back = ext._roundtrip(a)
    assert back.dtype == a.dtype
    assert back.shape == ((7, 5) if channels == 1 else shape)
    np.testing.assert_array_equal(back.reshape(a.shape), a)


def test_one_dimensional_bool_and_big_endian(ext):
    assert ext._matInfo(np.arange(6, dtype=np.float64)) == (6, 1, 1, 6)
    assert ext._matInfo(np.array([[True, False]])) == (1, 2, 1, 0)
    big = np.arange(12, dtype=">f4").reshape(3, 4)
    back = ext._roundtrip(big)
    assert back.dtype == np.float32
    np.testing.assert_array_equal(back, big.astype(np.float32))


@pytest.mark.parametrize("view", [
    lambda a: a[::2, ::3],
    lambda a: a[::-1],
    lambda a: a[:, ::-1],
    lambda a: a[::-2, ::-1, ::-1],
    lambda a: a[3:17, 5:31],
    lambda a: np.transpose(a, (1, 0, 2)),
    lambda a: a[..., 1:3],
])
def test_non_contiguous_and_negative_strides(ext, view):
    a = np.arange(24 * 40 * 3, dtype=np.float32).reshape(24, 40, 3)
    v = view(a)
    assert not v.flags.c_contiguous
    np.testing.assert_array_equal(ext._roundtrip(v), v)


def test_strided_input_gives_same_result_as_contiguous(db, small_setup):
    plant, sched, cam, shutter = small_setup
    big = make_scene(240, 320)
    strided = big[::2, ::2]
    flipped = np.ascontiguousarray(strided[::-1])[::-1]
    a = db.renderBlurred(np.ascontiguousarray(strided), plant, sched, cam, shutter)
    np.testing.assert_array_equal(db.renderBlurred(strided, plant, sched, cam, shutter), a)
    np.testing.assert_array_equal(db.renderBlurred(flipped, plant, sched, cam, shutter), a)
    gray = big[::2, ::2, 1]  # single channel, strided
    g = db.renderBlurred(gray, plant, sched, cam, shutter)
    assert g.shape == (120, 160)
    np.testing.assert_array_equal(g, db.renderBlurred(gray.copy(), plant, sched, cam, shutter))


def test_outputs_own_their_data(db, ext, small_setup):
    plant, sched, cam, shutter = small_setup
    sharp = make_scene(120, 160)
    out1 = db.renderBlurred(sharp, plant, sched, cam, shutter)
    assert out1.flags.owndata or out1.base is not None
    assert out1.flags.writeable
    keep = out1.copy()
    out1[:] = -1.0  # mutate the result, then run again: nothing was shared with a temporary
    out2 = db.renderBlurred(sharp, plant, sched, cam, shutter)
    np.testing.assert_array_equal(out2, keep)
    assert not np.shares_memory(out1, out2) and not np.shares_memory(out2, sharp)
    lin = db.srgbToLinear(sharp)  # float input already linear-ish: must still be a new buffer
    assert not np.shares_memory(lin, sharp)
    r = ext._roundtrip(sharp)
    assert not np.shares_memory(r, sharp)
    del out1, out2
    import gc
    gc.collect()
    np.testing.assert_array_equal(r, sharp)  # survives the collection of other results


@pytest.mark.parametrize("bad,match", [
    (np.zeros((4, 4, 5), np.float32), "5 channels"),
    (np.zeros((2, 2, 2, 2), np.float32), "4 dimensions"),
    (np.zeros((), np.float32), "0 dimensions"),
    (np.zeros((4, 4), np.int64), "dtype int64"),
    (np.zeros((4, 4), np.complex64), "dtype complex64"),
    (np.array([[object()]]), "object arrays"),
    (None, "is None"),
    ([[1, 2], [3]], "cannot be converted"),
])
def test_rejections_name_the_argument(ext, bad, match):
    with pytest.raises(ValueError, match=match) as info:
        ext._matInfo(bad)
    assert "argument 'a'" in str(info.value)
