// SPDX-License-Identifier: Apache-2.0
// Private: the operator a PsfBank is restored with, chosen by its shape.
#ifndef OPENCV_DYNBLUR_RESTORE_BANK_OPERATOR_FACTORY_HPP
#define OPENCV_DYNBLUR_RESTORE_BANK_OPERATOR_FACTORY_HPP

#include "restore/operators/blur_operator.hpp"

#include <memory>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief The operator that applies `bank` fastest: RowBankOperator when the bank has one node
column, TileBankOperator otherwise. `packed`: bfloat16 planes and weights. */
std::unique_ptr<BlurOperator> createBankOperator(const PsfBank& bank, bool pad, bool packed = false);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
