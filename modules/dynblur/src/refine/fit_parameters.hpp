// SPDX-License-Identifier: Apache-2.0
// Private: the parameters a MotionCorrection fit estimates, one table row each.
#ifndef OPENCV_DYNBLUR_REFINE_FIT_PARAMETERS_HPP
#define OPENCV_DYNBLUR_REFINE_FIT_PARAMETERS_HPP

#include <opencv2/dynblur/refinement.hpp>

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

//! What a fit parameter measures: it decides its value as told, its bounds and how reports print it.
enum FitQuantity
{
    FIT_CLOCK_OFFSET,  //!< seconds, told 0; searched FitSettings::maxTimeOffset either side of the start
    FIT_SCALE,         //!< a factor on a nominal value, told 1
    FIT_RATE           //!< rad/s, told 0
};

//! The motions a fit parameter corrects.
enum FitMotion
{
    FIT_PLANT_MOTION = 1,     //!< a plant's (schedule-driven) motion
    FIT_MEASURED_MOTION = 2,  //!< a measured motion (gyro log, orientations)
    FIT_MOUNT_MOTION = 4,     //!< a mount's motion: a chain of plant-driven axes (Mount::motion)
    FIT_ANY_MOTION = 7
};

/** @brief One parameter of the fit: the MotionCorrection field it sets (its forward model is that
field's use in MotionCorrection::correctShutter, correctPlant and correctedView), the flag that turns
it on, the motions and shutters it applies to, and how the fit treats it. The fit works in "fit
units", chosen so that one unit moves the image by comparable amounts; every number below but
`unit` is in fit units. */
struct FitParameter
{
    const char* name;       //!< for messages: "time offset", "gyro bias x"
    const char* group;      //!< its flag's name in messages: "time offset", "plant", "gyro bias"
    const char* key;        //!< the flag's short name in command lines: "offset", "line-delay", "plant", "bias"
    const char* flagName;   //!< "REFINE_TIME_OFFSET"
    int flag;               //!< the MotionRefinement flag that turns it on (several parameters may share one)
    FitQuantity quantity;
    int motions;            //!< FitMotion flags: the motions it corrects
    int axis;               //!< the mount axis whose plant it scales (one plant's scales are axis 0's); -1: none
    bool rollingOnly;       //!< observed only through a rolling shutter's rows (the line delay)
    bool inRefineAll;       //!< part of REFINE_ALL
    double unit;            //!< one fit unit in the field's own unit (s, ×, rad/s)
    double step;            //!< the Jacobian's forward-difference step
    double tolerance;       //!< a step below this in every parameter ends a level's fit
    double searchHalfWidth; //!< searched within this of its value as told (a clock offset: FitSettings)
    double priorDeviation;  //!< the weak prior toward the start
    double observable;      //!< a coarse-fit standard deviation above it: not observed by the frames
    /** the clock offset's scan is repeated with this parameter this far either side of its start (0:
        not): an error in ωn delays the end of a move by a growing amount, which no offset matches */
    double scanStep;
    double (*get)(const MotionCorrection&);
    void (*set)(MotionCorrection&, double);
    double& (*deviation)(TimingCalibration&);  //!< where calibrateTiming reports its standard deviation
};

/* The table. A unit step moves the image by comparable amounts: the offset in milliseconds, the line
   delay, ωn and the rate scale in percent, ζ in tens of percent (the blur is least sensitive to it),
   the gyro bias in mrad/s. Scales are searched within ±15 % (line delay), ±10 % (ωn), ±50 % (ζ, and
   the rate scale: a sweep about the arm at arm's length, 0.6 m, over a scene 1 m away lengthens the
   image's motion by about 60 %), the bias within ±40 mrad/s (2.3 °/s: a phone's gyro bias is a
   fraction of that). The weak prior decides only what the frames do not observe (a global shutter's
   line delay, ζ in a frame that sees no ringing, a bias over a short still-to-frame interval). A
   coarse-fit deviation above 0.3 ms, 3 %, 2 %, 25 %, 5 mrad/s or 3 % means the frames' moving rows see
   content the reference never saw, or motion that does not depend on the parameter. */
// name, group, key, flag; quantity, motions, mount axis, rolling only, in REFINE_ALL;
// unit, step, tolerance, search half-width, prior deviation, observable, scan step; the field; its
// deviation. Along a ridge (motion_fit.cpp) the last rows are held first.
inline const FitParameter kFitTable[] = {
    {"time offset", "time offset", "offset", "REFINE_TIME_OFFSET", REFINE_TIME_OFFSET,
     FIT_CLOCK_OFFSET, FIT_ANY_MOTION, -1, false, true,
     1e-3, 0.1, 0.01, 0, 2, 0.3, 0,
     [](const MotionCorrection& c) { return c.timeOffset; }, [](MotionCorrection& c, double v) { c.timeOffset = v; },
     [](TimingCalibration& t) -> double& { return t.timeOffsetStd; }},
    {"line delay", "line delay", "line-delay", "REFINE_LINE_DELAY", REFINE_LINE_DELAY,
     FIT_SCALE, FIT_ANY_MOTION, -1, true, true,
     1e-2, 1, 0.05, 15, 10, 3, 0,
     [](const MotionCorrection& c) { return c.lineDelayScale; }, [](MotionCorrection& c, double v) { c.lineDelayScale = v; },
     [](TimingCalibration& t) -> double& { return t.lineDelayScaleStd; }},
    {"natural frequency", "plant", "plant", "REFINE_PLANT", REFINE_PLANT,
     FIT_SCALE, FIT_PLANT_MOTION | FIT_MOUNT_MOTION, 0, false, true,
     1e-2, 1, 0.05, 10, 5, 2, 4,
     [](const MotionCorrection& c) { return c.naturalFreqScale; }, [](MotionCorrection& c, double v) { c.naturalFreqScale = v; },
     [](TimingCalibration& t) -> double& { return t.naturalFreqScaleStd; }},
    {"damping ratio", "plant", "plant", "REFINE_PLANT", REFINE_PLANT,
     FIT_SCALE, FIT_PLANT_MOTION | FIT_MOUNT_MOTION, 0, false, true,
     1e-1, 1, 0.1, 5, 3, 2.5, 0,
     [](const MotionCorrection& c) { return c.dampingScale; }, [](MotionCorrection& c, double v) { c.dampingScale = v; },
     [](TimingCalibration& t) -> double& { return t.dampingScaleStd; }},
    {"gyro bias x", "gyro bias", "bias", "REFINE_GYRO_BIAS", REFINE_GYRO_BIAS,
     FIT_RATE, FIT_MEASURED_MOTION, -1, false, false,
     1e-3, 1, 0.1, 40, 20, 5, 0,
     [](const MotionCorrection& c) { return c.gyroBias[0]; }, [](MotionCorrection& c, double v) { c.gyroBias[0] = v; },
     [](TimingCalibration& t) -> double& { return t.gyroBiasStd[0]; }},
    {"gyro bias y", "gyro bias", "bias", "REFINE_GYRO_BIAS", REFINE_GYRO_BIAS,
     FIT_RATE, FIT_MEASURED_MOTION, -1, false, false,
     1e-3, 1, 0.1, 40, 20, 5, 0,
     [](const MotionCorrection& c) { return c.gyroBias[1]; }, [](MotionCorrection& c, double v) { c.gyroBias[1] = v; },
     [](TimingCalibration& t) -> double& { return t.gyroBiasStd[1]; }},
    {"gyro bias z", "gyro bias", "bias", "REFINE_GYRO_BIAS", REFINE_GYRO_BIAS,
     FIT_RATE, FIT_MEASURED_MOTION, -1, false, false,
     1e-3, 1, 0.1, 40, 20, 5, 0,
     [](const MotionCorrection& c) { return c.gyroBias[2]; }, [](MotionCorrection& c, double v) { c.gyroBias[2] = v; },
     [](TimingCalibration& t) -> double& { return t.gyroBiasStd[2]; }},
    {"rate scale", "rate scale", "rate-scale", "REFINE_RATE_SCALE", REFINE_RATE_SCALE,
     FIT_SCALE, FIT_MEASURED_MOTION, -1, false, false,
     1e-2, 1, 0.05, 50, 20, 3, 0,
     [](const MotionCorrection& c) { return c.rateScale; }, [](MotionCorrection& c, double v) { c.rateScale = v; },
     [](TimingCalibration& t) -> double& { return t.rateScaleStd; }},
    // A mount's axes 1 and 2, as its base's (axis 0's: the plant's rows above).
    {"natural frequency, axis 1", "plant", "plant", "REFINE_PLANT", REFINE_PLANT,
     FIT_SCALE, FIT_MOUNT_MOTION, 1, false, true,
     1e-2, 1, 0.05, 10, 5, 2, 4,
     [](const MotionCorrection& c) { return c.axisNaturalFreqScales[0]; },
     [](MotionCorrection& c, double v) { c.axisNaturalFreqScales[0] = v; },
     [](TimingCalibration& t) -> double& { return t.axisNaturalFreqScaleStd[0]; }},
    {"damping ratio, axis 1", "plant", "plant", "REFINE_PLANT", REFINE_PLANT,
     FIT_SCALE, FIT_MOUNT_MOTION, 1, false, true,
     1e-1, 1, 0.1, 5, 3, 2.5, 0,
     [](const MotionCorrection& c) { return c.axisDampingScales[0]; },
     [](MotionCorrection& c, double v) { c.axisDampingScales[0] = v; },
     [](TimingCalibration& t) -> double& { return t.axisDampingScaleStd[0]; }},
    {"natural frequency, axis 2", "plant", "plant", "REFINE_PLANT", REFINE_PLANT,
     FIT_SCALE, FIT_MOUNT_MOTION, 2, false, true,
     1e-2, 1, 0.05, 10, 5, 2, 0,
     [](const MotionCorrection& c) { return c.axisNaturalFreqScales[1]; },
     [](MotionCorrection& c, double v) { c.axisNaturalFreqScales[1] = v; },
     [](TimingCalibration& t) -> double& { return t.axisNaturalFreqScaleStd[1]; }},
    {"damping ratio, axis 2", "plant", "plant", "REFINE_PLANT", REFINE_PLANT,
     FIT_SCALE, FIT_MOUNT_MOTION, 2, false, true,
     1e-1, 1, 0.1, 5, 3, 2.5, 0,
     [](const MotionCorrection& c) { return c.axisDampingScales[1]; },
     [](MotionCorrection& c, double v) { c.axisDampingScales[1] = v; },
     [](TimingCalibration& t) -> double& { return t.axisDampingScaleStd[1]; }},
};

const int kFitParameters = int(sizeof(kFitTable) / sizeof(kFitTable[0]));
static_assert(kFitParameters < 31, "MotionCorrection::heldParameters holds one bit per parameter in an int");
typedef Vec<double, kFitParameters> FitVector;
typedef Matx<double, kFitParameters, kFitParameters> FitMatrix;

//! The fitted parameters of `c` in fit units, relative to their values as told.
FitVector toFitUnits(const MotionCorrection& c);
//! `like` with every fitted parameter set from `q` (fit units); its other fields kept.
MotionCorrection fromFitUnits(const FitVector& q, const MotionCorrection& like);

/** @brief The parameters `flags` turns on for frames of the given kind, in table order.
@param motion the frames' FitMotion (one of them).
@param rolling some frame has a rolling shutter.
@param axes a mount's axes (parameters of further axes are left out); 1 for other motions. */
std::vector<int> flaggedParameters(int flags, int motion, bool rolling, int axes);

/* Parameters as bits: bit j stands for kFitTable[j] (MotionCorrection::heldParameters). */

//! The flags of the parameters whose bits `bits` sets, combined.
int flagsOfParameters(int bits);

//! "natural frequency, axis 1 and damping ratio, axis 1": the parameters whose bits `bits` sets, for messages.
String parameterNames(int bits);

//! Every flag of the table, combined: what a flags argument may hold.
int allRefinementFlags();

//! The table's flags that correct `motion` (FitMotion), combined.
int refinementFlagsFor(int motion);

//! "time offset, line delay, plant and gyro bias": the parameters of MotionRefinement `flags`, for messages.
String refinementFlagNames(int flags);

/** @brief "REFINE_TIME_OFFSET (1), REFINE_LINE_DELAY (2) and REFINE_GYRO_BIAS (8)": the flags among
`flags`, for the messages that check a flags argument. */
String refinementFlagList(int flags);

/** @brief "time offset %+.2f ms at its search bound (...)": why the fit refused parameter `j` that
ended at value `value` (the field's unit) against its bounds around `start` (the field's unit).
@param maxTimeOffset the clock offset's search half-width, seconds. */
String pinnedNote(int j, double value, double start, double maxTimeOffset);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
