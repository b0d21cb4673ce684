# SPDX-License-Identifier: Apache-2.0
"""Camera calibration from Python: the same ViSP calibration as the C++ tool, on the shared views."""
import glob
import os

import numpy as np
import pytest

DATA = os.environ.get("DYNBLUR_TEST_DATA",
                      os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data"))
VIEWS = sorted(glob.glob(os.path.join(DATA, "left*.jpg")))


@pytest.fixture(scope="module")
def views(require_data):
    require_data(len(VIEWS) >= 3, f"chessboard views left*.jpg not found in {DATA} (set DYNBLUR_TEST_DATA)")
    return VIEWS


def test_calibration_from_files_matches_opencv(db, views):
    import cv2
    calib = db.calibrateCameraViSP(views, boardSize=(9, 6), squareSize=0.025)
    assert calib.globalResidual <= 0.5
    assert calib.usedViews() >= 3 and len(calib.viewStatus) == len(views)
    used = [i for i, u in enumerate(calib.viewUsed) if u]
    # OpenCV's calibrateCamera on the very corners the library found, one radial term.
    board = np.zeros((54, 3), np.float32)
    board[:, :2] = np.mgrid[0:9, 0:6].T.reshape(-1, 2) * 0.025
    corners = [calib.imagePoints[i].reshape(-1, 1, 2) for i in used]
    flags = cv2.CALIB_FIX_K2 | cv2.CALIB_FIX_K3 | cv2.CALIB_ZERO_TANGENT_DIST
    _, k, _, _, _ = cv2.calibrateCamera([board] * len(corners), corners, calib.imageSize, None, None, flags=flags)
    print(f"ViSP px={calib.px:.2f} py={calib.py:.2f} u0={calib.u0:.2f} v0={calib.v0:.2f} residual "
          f"{calib.globalResidual:.3f} px; OpenCV fx={k[0, 0]:.2f} fy={k[1, 1]:.2f} cx={k[0, 2]:.2f} cy={k[1, 2]:.2f}")
    assert abs(calib.px / k[0, 0] - 1) <= 0.01 and abs(calib.py / k[1, 1] - 1) <= 0.01
    assert abs(calib.u0 - k[0, 2]) <= 3 and abs(calib.v0 - k[1, 2]) <= 3
    cam = calib.cameraModel()
    assert cam.getImageSize() == calib.imageSize and cam.getKud() == pytest.approx(calib.kud)
    assert calib.cameraMatrix().shape == (3, 3) and calib.openCVDistortion().size == 5


def test_corner_detection_and_in_memory_views(db, views):
    import cv2
    images = [cv2.imread(p, cv2.IMREAD_GRAYSCALE) for p in views[:4]]
    found, corners = db.detectChessboardCorners(images[0], (9, 6))
    assert found and corners.shape == (54, 2) and corners.dtype == np.float32
    blank = np.zeros_like(images[0])
    found, corners = db.detectChessboardCorners(blank, (9, 6))
    assert not found and corners is None
    calib = db.calibrateCameraViSPImages(images + [blank], ["a", "b", "c", "d", "blank"], (9, 6), 0.025)
    assert calib.viewNames[-1] == "blank" and calib.viewUsed[-1] == 0
    assert "not found" in calib.viewStatus[-1]


def test_too_few_views_is_an_error_naming_them(db, views):
    with pytest.raises(db.error, match="3"):
        db.calibrateCameraViSP(views[:2], boardSize=(9, 6), squareSize=0.025)
    with pytest.raises(db.error):
        db.calibrateCameraViSP(views, boardSize=(9, 6), squareSize=-1.0)
