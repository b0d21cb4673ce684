// Private: the linear blur operators that Richardson–Lucy inverts, and their exact adjoints.
// tests/test_deconv.cpp includes this header to check <A x, y> == <x, Aᵀ y>.
#ifndef OPENCV_DYNBLUR_DECONV_OPERATOR_HPP
#define OPENCV_DYNBLUR_DECONV_OPERATOR_HPP

#include "restore/bank_geometry.hpp"
#include "restore/bank_operator.hpp"
#include "restore/blur_operator.hpp"
#include "restore/displacement.hpp"
#include "restore/packed_gather.hpp"
#include "restore/row_arithmetic.hpp"
#include "restore/row_bank_operator.hpp"
#include "restore/tile_bank_operator.hpp"
#include "restore/uniform_operator.hpp"

#endif
