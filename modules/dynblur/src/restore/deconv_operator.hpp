// SPDX-License-Identifier: Apache-2.0
// Private: the linear blur operators that Richardson–Lucy inverts, and their exact adjoints.
// tests/restore/test_deconv_*.cpp include this header to check <A x, y> == <x, Aᵀ y>.
#ifndef OPENCV_DYNBLUR_DECONV_OPERATOR_HPP
#define OPENCV_DYNBLUR_DECONV_OPERATOR_HPP

#include "restore/operators/bank_geometry.hpp"
#include "restore/operators/bank_operator.hpp"
#include "restore/operators/bank_operator_factory.hpp"
#include "restore/operators/blur_operator.hpp"
#include "restore/operators/displacement.hpp"
#include "restore/operators/packed_gather.hpp"
#include "restore/row_arithmetic.hpp"
#include "restore/operators/row_bank_operator.hpp"
#include "restore/operators/tile_bank_operator.hpp"
#include "restore/operators/uniform_operator.hpp"

#endif
