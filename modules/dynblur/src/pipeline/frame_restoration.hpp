// SPDX-License-Identifier: Apache-2.0
// Private: DynamicDeblurrer's restoration stage, from a frame and its PSF bank to the restored frame
// in the frame's own encoding.
#ifndef OPENCV_DYNBLUR_PIPELINE_FRAME_RESTORATION_HPP
#define OPENCV_DYNBLUR_PIPELINE_FRAME_RESTORATION_HPP

#include <opencv2/dynblur/deblurrer.hpp>

#include "motion/view_motion.hpp"
#include "pipeline/frame_sharpness.hpp"
#include "restore/deconv_rl.hpp"

namespace cv {
namespace dynblur {
namespace detail {

//! How a frame is restored: DynamicDeblurrer's restoration settings.
struct RestorationSettings
{
    int psfModel = PSF_AUTO;  //!< PsfModel (the half-resolution color's bank takes the same)
    int method = DEBLUR_RICHARDSON_LUCY;                   //!< DeblurMethod
    int colorResolution = DEBLUR_COLOR_FULL_RESOLUTION;    //!< DeblurColorResolution
    int unobservedFill = UNOBSERVED_RECORDED;              //!< UnobservedFill
    RLParams params;                                       //!< as set (getRLParams)
    bool iterationsByNeed = false;  //!< DEBLUR_PRESET_FRAME_RATE: each frame's iterations from its bank
    double wienerNoiseToSignal = 1e-2;                     //!< DEBLUR_WIENER's noise-to-signal ratio
};

//! The frame returned as it came, every pixel valid.
void passThrough(const Mat& input, OutputArray restored, OutputArray validMask);

/** @brief The restoration stage: decodes a frame into linear light (sRGB, alpha), restores it with
the method its settings choose (Wiener, Richardson–Lucy in full color, or the color at half
resolution), encodes the result as the frame was, and fills what the frame never saw. It keeps its
workspaces between frames, so a stream of frames faults in no fresh memory. */
class FrameRestorer
{
public:
    //! @param camera the frames' camera (its half-size twin serves the color at half resolution).
    explicit FrameRestorer(const Ptr<CameraModel>& camera);

    /** @brief Restores `input` (checked by the caller: a frame of the camera).
    @param bank its kernels for `view` read by `shutter` (the corrected shutter).
    @param generator the generator of `bank`, whose settings the half-resolution color's follow.
    @param settings the restoration settings.
    @param restored output, as `input`; may be `input` itself (restored in place).
    @param validMask optional output, CV_8U, 255 where the frame observed the restored pixel. */
    void restore(const Mat& input, const PsfBank& bank, const ViewMotion& view, const RollingShutter& shutter,
                 const PsfGenerator& generator, const RestorationSettings& settings, OutputArray restored,
                 OutputArray validMask);

    /** @brief A sharp frame's rows moved back to the reference view without deconvolution: each
    pixel of the view read from where the frame recorded it (recordedPositions), bicubic, in the
    frame's own encoding; alpha passes through. Returns false, having written nothing, where those
    positions cannot be found (rows folded over one another).
    @param input the frame (checked by the caller: a frame of the camera).
    @param sharpness its sharpness, whose mean displacements place the rows.
    @param unobservedFill UnobservedFill: what fills the pixels the frame never saw.
    @param restored output, as `input`; may be `input` itself.
    @param validMask optional output, CV_8U, 255 where the frame observed the pixel. */
    bool moveBack(const Mat& input, const FrameSharpness& sharpness, int unobservedFill, OutputArray restored,
                  OutputArray validMask);

private:
    /* The restoration of `linear` by the method set, in [0, 1]: straight into `restored` when
       `direct` (8-bit there when the input is, with the color at half resolution), else into latent_. */
    Mat restoreLinear(const Mat& linear, const PsfBank& bank, const ViewMotion& view, const RollingShutter& shutter,
                      const PsfGenerator& generator, const RestorationSettings& settings, const RLParams& params,
                      bool halfColor, bool direct, int inputDepth, OutputArray restored);
    /* DEBLUR_COLOR_HALF_RESOLUTION: the color phase on the halved frame, with a half-size camera's
       kernels; the luminance with every iteration at full resolution; then one pass that upsamples the
       color, scales it to the luminance and writes it in `depth` (CV_8U: sRGB). */
    void restoreWithHalfColor(const Mat& frame, const PsfBank& bank, const ViewMotion& view,
                              const RollingShutter& shutter, const PsfGenerator& generator, int psfModel,
                              const RLParams& params, const _OutputArray& target, int depth);
    //! The generator of the half-size camera, with `generator`'s settings halved where they count pixels.
    const Ptr<PsfGenerator>& halfGenerator(const PsfGenerator& generator, const PsfBank& bank);
    //! An 8-bit sRGB frame as linear light, in a buffer kept between frames (a fresh one faults in its pages).
    Mat linearized(const Mat& color);

    Ptr<CameraModel> camera_;
    Ptr<CameraModel> halfCamera_;  // created when first needed
    Ptr<PsfGenerator> halfGenerator_;
    RLWorkspace workspace_, halfWorkspace_;
    Mat linear_, latent_, mask_;
    Mat mapX_, mapY_;  // moveBack's: where the frame recorded each pixel of the reference view
    Mat halfColor_, luminance_;  // DEBLUR_COLOR_HALF_RESOLUTION's planes
};

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
