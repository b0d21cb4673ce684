# SPDX-License-Identifier: Apache-2.0
"""Cross-check: cv::dynblur::richardsonLucy agrees with scikit-image's richardson_lucy.

scikit-image (0.19+) runs ``richardson_lucy(image, psf, num_iter, clip, filter_epsilon)`` from a
constant 0.5 start with scipy's zero-padded ``convolve(..., mode='same')``; the C++ side runs
RL_BOUNDARY_ZERO from the same start, without acceleration, damping or TV. The C++ program
``dynblur_rl_tool`` is found in $DYNBLUR_BUILD_DIR/tests (default /work/main/build, i.e. the
repository's build/ folder), or at $DYNBLUR_RL_TOOL.
"""
import os
import pathlib
import subprocess

import numpy as np
import pytest
from skimage.restoration import richardson_lucy

REPO = pathlib.Path(__file__).resolve().parents[2]


def tool_path():
    explicit = os.environ.get("DYNBLUR_RL_TOOL")
    if explicit:
        return pathlib.Path(explicit)
    build = pathlib.Path(os.environ.get("DYNBLUR_BUILD_DIR", REPO / "build"))
    return build / "tests" / "dynblur_rl_tool"


def run_tool(image, psf, iterations, tmp_path):
    tool = tool_path()
    if not tool.exists():
        pytest.fail(f"{tool} not found: build the dynblur_rl_tool target or set DYNBLUR_BUILD_DIR")
    image_file, psf_file, out_file = tmp_path / "image.f32", tmp_path / "psf.f32", tmp_path / "out.f32"
    image.astype("<f4").tofile(image_file)
    psf.astype("<f4").tofile(psf_file)
    subprocess.run([str(tool), str(image_file), str(image.shape[0]), str(image.shape[1]), str(psf_file),
                    str(psf.shape[0]), str(psf.shape[1]), str(iterations), str(out_file)], check=True)
    return np.fromfile(out_file, dtype="<f4").reshape(image.shape)


def motion_psf(rows, cols, seed):
    rng = np.random.default_rng(seed)
    psf = np.zeros((rows, cols), np.float32)
    # A bent path plus a faint asymmetric halo: a flipped kernel would not match.
    for t in np.linspace(0, 1, 60):
        y = int(round((rows - 1) * (0.5 + 0.4 * np.sin(2.5 * t) - 0.2)))
        x = int(round((cols - 1) * t))
        psf[min(max(y, 0), rows - 1), x] += 1
    psf += 0.01 * rng.random(psf.shape, dtype=np.float32)
    return (psf / psf.sum()).astype(np.float32)


def make_image(shape, seed):
    from scipy.ndimage import gaussian_filter
    rng = np.random.default_rng(seed)
    image = gaussian_filter(rng.random(shape), 2.0)
    image = (image - image.min()) / (image.max() - image.min())
    return (0.05 + 0.9 * image).astype(np.float32)


@pytest.mark.parametrize("shape,psf_shape", [((64, 80), (7, 15)), ((97, 51), (9, 5)), ((40, 40), (1, 11))])
def test_matches_skimage_after_10_iterations(shape, psf_shape, tmp_path):
    from scipy.signal import convolve
    latent = make_image(shape, 1)
    psf = motion_psf(*psf_shape, seed=2)
    blurred = convolve(latent, psf, mode="same").astype(np.float32)
    blurred = np.clip(blurred + np.random.default_rng(3).normal(0, 0.003, shape), 0, None).astype(np.float32)

    expected = richardson_lucy(blurred, psf, num_iter=10, clip=False)
    got = run_tool(blurred, psf, 10, tmp_path)
    assert expected.dtype == np.float32
    assert np.max(np.abs(expected - 0.5)) > 0.1  # the iterations moved the estimate
    print(f"max |dynblur - skimage| = {np.max(np.abs(got - expected)):.2e}")
    assert np.max(np.abs(got - expected)) < 1e-4


def test_disagrees_when_the_kernel_is_flipped(tmp_path):
    """The comparison can fail: a flipped kernel gives a clearly different result."""
    from scipy.signal import convolve
    latent = make_image((48, 60), 4)
    psf = motion_psf(7, 13, seed=5)
    blurred = convolve(latent, psf, mode="same").astype(np.float32)
    expected = richardson_lucy(blurred, psf[::-1, ::-1].copy(), num_iter=10, clip=False)
    got = run_tool(blurred, psf, 10, tmp_path)
    assert np.max(np.abs(got - expected)) > 1e-2
