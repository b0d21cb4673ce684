// SPDX-License-Identifier: Apache-2.0
#include "restore_video.hpp"

#include "restoration_options.hpp"  // samples/support

namespace dynblur_samples {

RestorationSettings::RestorationSettings(const CliArgs& args)
    : preset(deblurPresetFromName(args.str("preset"))), psfModel(psfModelFromName(args.str("model")))
{
}

void RestorationSettings::apply(cv::dynblur::DynamicDeblurrer& deblurrer) const
{
    deblurrer.setPreset(preset);
    deblurrer.setPsfModel(psfModel);
}

std::string defaultCameraPath()
{
    return std::string(DYNBLUR_CALIB_DIR) + "/c270_nominal.xml";
}

}  // namespace dynblur_samples
