# SPDX-License-Identifier: Apache-2.0
"""cv2.dynblur: the `dynblur` package seen from OpenCV's namespace.

opencv-python's loader imports every package folder inside cv2/ as cv2.<name>; this one makes
cv2.dynblur the very same module object as `import dynblur`.
"""
import sys

import dynblur as _dynblur

sys.modules[__name__] = _dynblur
