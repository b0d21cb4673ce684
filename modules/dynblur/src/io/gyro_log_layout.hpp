// SPDX-License-Identifier: Apache-2.0
// The layout of a gyro log: where its samples start, which fields hold the time and the three rates,
// their units and the axis string, as a gcsv header or a CSV header row (with GyroLogOptions) says.
#ifndef DYNBLUR_SRC_IO_GYRO_LOG_LAYOUT_HPP
#define DYNBLUR_SRC_IO_GYRO_LOG_LAYOUT_HPP

#include "io/gyro_log_text.hpp"

#include <opencv2/dynblur/gyro_log.hpp>

#include <limits>
#include <string>
#include <vector>

namespace cv {
namespace dynblur {
namespace gyro_log {

//! Where a log's samples are and how to read them.
struct LogLayout
{
    std::string name;                  //!< GyroLog::layout
    size_t firstRow = 0;               //!< line index of the first data row
    std::vector<std::string> columns;  //!< one name per field, for messages ("column 3" without a header row)
    bool headerRow = true;             //!< the file names its columns (a gcsv column row or a CSV header row)
    int time = 0;                      //!< field index of the time
    int rate[3] = {1, 2, 3};           //!< field indices of the rates about the gyro's x, y, z
    double secondsPerUnit = 1.0;
    double radPerUnit = 1.0;
    std::string orientation = "XYZ";   //!< the layout's axis string (a gcsv file's own, "" when absent)
    bool gyroflowAxes = false;         //!< the axis string maps to Gyroflow's frame (GyroLogOptions::gcsvAxes)
    bool everyFieldNumeric = false;    //!< gcsv: every field must be a number, not only those read
    std::string id;                    //!< gcsv `id`
    double frameReadoutTime = std::numeric_limits<double>::quiet_NaN();  //!< seconds
    int frameReadoutDirection = READOUT_DIRECTION_UNKNOWN;
};

/** The layout of `text`: a gcsv header, or a CSV whose header row names a known layout or whose
    columns `options` give, with the options' units and axis string applied. Fails naming the line. */
LogLayout readLayout(const LogText& text, const GyroLogOptions& options);

}  // namespace gyro_log
}  // namespace dynblur
}  // namespace cv

#endif
