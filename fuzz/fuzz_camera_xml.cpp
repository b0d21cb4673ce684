// SPDX-License-Identifier: Apache-2.0
// Fuzzes CameraModel::load, the reader of ViSP camera XML files (calibration output, --camera of the
// demo): the first <camera> name scan of camera.cpp, then ViSP's vpXmlParserCamera, then the
// intrinsics checks. A camera that loads must give finite mappings for pixels in its image.
#include "fuzz_common.hpp"

#include <opencv2/dynblur.hpp>

#include <cmath>

using namespace cv::dynblur;

namespace {

void exercise(const cv::Ptr<CameraModel>& camera)
{
    const cv::Size size = camera->getImageSize();
    if (size.width <= 0 || size.height <= 0 || !(camera->getFx() > 0) || !(camera->getFy() > 0))
        std::abort();  // load() promised a usable camera
    const cv::Point2d corner(size.width - 1, size.height - 1);
    const cv::Point2d n = camera->pixelToNormalized(corner);
    const cv::Point2d p = camera->normalizedToPixel(n);
    (void)p;  // finite or not: distortion coefficients may be wild; UBSan checks the arithmetic
    (void)camera->viewToReference(corner, 0.1);
    (void)camera->cameraMatrix();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string& path = dynblur_fuzz::writeScratchFile(data, size, "_camera.xml");
    try
    {
        exercise(CameraModel::load(path));
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
    }
    // The selecting form: a named camera at a given image size.
    try
    {
        exercise(CameraModel::load(path, "C270", 1280, 960));
    }
    catch (const cv::Exception& e)
    {
        dynblur_fuzz::checkRefusal(e);
    }
    return 0;
}
