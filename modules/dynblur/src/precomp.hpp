// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_PRECOMP_HPP
#define OPENCV_DYNBLUR_PRECOMP_HPP

#include "opencv2/dynblur.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#endif
