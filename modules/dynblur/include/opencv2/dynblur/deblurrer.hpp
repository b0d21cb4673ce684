#ifndef OPENCV_DYNBLUR_DEBLURRER_HPP
#define OPENCV_DYNBLUR_DEBLURRER_HPP

#include <opencv2/dynblur/deconv.hpp>
#include <opencv2/dynblur/psf.hpp>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_restoration
//! @{

//! Restoration method used by DynamicDeblurrer.
enum DeblurMethod
{
    DEBLUR_RICHARDSON_LUCY = 0,  //!< spatially variant Richardson–Lucy (default)
    DEBLUR_WIENER = 1            //!< Wiener: fast, non-iterative
};

/** @brief Restores frames taken while the positioner moves: the blur of every pixel is predicted
from the plant and the commands, then undone @cite DynblurSeed.

deblur() follows one frame through the pipeline: the exposure window (classifyExposure), the
kernels (PsfGenerator), the restoration (richardsonLucyVariant). The result is the
global-shutter, motion-free view at θ_ref: rolling-shutter geometry and blur are undone together.
*/
class CV_EXPORTS_W DynamicDeblurrer : public Algorithm
{
public:
    /** @param plant the positioner. @param camera the camera. */
    CV_WRAP static Ptr<DynamicDeblurrer> create(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera);

    /** @brief Restores one frame.
    @param frame CV_8U (sRGB, linearised for restoration and encoded back) or CV_32F (linear,
           [0,1], as a sensor delivers it: clip noisy data first), 1, 3 or 4 channels, the camera's
           image size.
    @param schedule the command in force around the frame.
    @param shutter the frame's timing (rows = frame height).
    @param restored output, same size, type and channels as frame. A frame in window IV comes
           back unchanged.
    @param thetaRef reference angle, radians; NaN: the schedule's final resting angle.
    @param validMask optional output, CV_8U, 255 where the frame observed the restored pixel. */
    CV_WRAP virtual void deblur(InputArray frame, const SwitchSchedule& schedule, const RollingShutter& shutter,
                                OutputArray restored, double thetaRef = std::numeric_limits<double>::quiet_NaN(),
                                OutputArray validMask = noArray()) = 0;

    CV_WRAP virtual int getPsfModel() const = 0;            //!< PsfModel (default PSF_TILES, the most accurate)
    CV_WRAP virtual void setPsfModel(int model) = 0;
    CV_WRAP virtual int getMethod() const = 0;              //!< DeblurMethod
    CV_WRAP virtual void setMethod(int method) = 0;
    /** @brief Restoration options; default RLParams() with automatic damping (damping = NaN: 3σ of
    the frame's estimated noise). For frame rate with colour frames use PSF_ROWS, 10 iterations and
    colorIterations = 3 (the quality test DeblurQuality.RollingShutterWindowIII* checks that setting). */
    CV_WRAP virtual RLParams getRLParams() const = 0;
    CV_WRAP virtual void setRLParams(const RLParams& params) = 0;
    /** @brief Exposure window of the last frame passed to deblur() (0 before the first). */
    CV_WRAP virtual int getLastExposureWindow() const = 0;
    /** @brief Kernels used for the last frame. */
    CV_WRAP virtual PsfBank getLastPsfBank() const = 0;
    CV_WRAP virtual Ptr<PsfGenerator> getPsfGenerator() const = 0;
};

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
