// SPDX-License-Identifier: Apache-2.0
#include "restore/operators/bank_operator_factory.hpp"

#include "restore/operators/row_bank_operator.hpp"
#include "restore/operators/tile_bank_operator.hpp"

namespace cv {
namespace dynblur {
namespace detail {

std::unique_ptr<BlurOperator> createBankOperator(const PsfBank& bank, bool pad, bool packed)
{
    if (bank.nodeCols.size() == 1)
        return std::unique_ptr<BlurOperator>(new RowBankOperator(bank, pad, packed));
    return std::unique_ptr<BlurOperator>(new TileBankOperator(bank, pad, packed));
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
