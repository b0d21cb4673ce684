# SPDX-License-Identifier: Apache-2.0
"""dynblur: dynamics-based motion deblurring for a robotic camera (Python bindings of cv::dynblur).

The blur of a frame taken while the camera positioner moves is predicted from the plant's
dynamics and the commands it was sent, row by row for rolling-shutter sensors, and undone with
Richardson–Lucy deconvolution. The API mirrors the C++ names (``cv::dynblur::Plant`` is
``dynblur.Plant``, ``Ptr<X> X::create(...)`` is ``X.create(...)``, OutputArray results are
returned as numpy arrays). Also available as ``cv2.dynblur`` after ``import cv2`` when
opencv-python(-headless) is installed.

Units are SI: seconds, radians, pixels.

Errors reported by the C++ library (cv::Exception) are raised as :class:`dynblur.error`, a
subclass of ``cv2.error`` when cv2 can be imported (else of ``Exception``), whose message is the
C++ one (attributes ``code``, ``err``, ``func``, ``file``, ``line``, ``msg`` as in cv2.error).
Arguments that cannot be converted (unsupported dtype, > 4 channels, > 3 dimensions, object
arrays, None) raise ``ValueError`` naming the argument.

Long calls (plan, identify, renderBlurred, richardsonLucy*, wienerDeconvolve, deblur, generate)
release the GIL, so frames can be restored in one thread while another captures.

``GyroLog.fromVideo(path)`` reads the gyro a video embeds (GoPro, Sony, Insta360, DJI, ...) with the
optional telemetry-parser package; ``python -m dynblur.extract_gyro clip.mp4 clip.gcsv`` writes it as gcsv.
"""
from . import _dynblur
from ._dynblur import *  # noqa: F401,F403
from ._dynblur import __opencv_version__  # noqa: F401

__version__ = "0.1.0"

try:  # cv2's loader imports cv2/dynblur, which maps back to this (already registered) module
    import cv2 as _cv2
    _base_error = getattr(_cv2, "error", Exception)
except ImportError:
    _cv2 = None
    _base_error = Exception

if _cv2 is not None and not hasattr(_cv2, "dynblur"):
    # An editable install has no cv2/dynblur folder for cv2's loader to find: attach ourselves.
    import sys as _sys
    _cv2.dynblur = _sys.modules[__name__]
    _sys.modules.setdefault("cv2.dynblur", _sys.modules[__name__])


class error(_base_error):
    """An error reported by the C++ library (cv::Exception); a cv2.error when cv2 is installed."""


error.__module__ = "dynblur"
_dynblur._set_error_class(error)

# A video's embedded gyro, read by telemetry-parser (pure Python: dynblur/extract_gyro.py).
from .extract_gyro import from_video as _from_video  # noqa: E402

GyroLog.fromVideo = staticmethod(_from_video)  # noqa: F405

__all__ = [name for name in dir(_dynblur) if not name.startswith("_")]
