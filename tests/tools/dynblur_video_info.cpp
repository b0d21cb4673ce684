// SPDX-License-Identifier: Apache-2.0
// Describes a video as the programs read it (samples/support/video_clip.hpp), so that the CLI tests
// can check what a program wrote: its frame count, frame size, stream rate and frame times.
//
//   dynblur_video_info VIDEO
//
// prints "frames N size WxH fps F first T0 last T1 clock C" (times in seconds) and exits 0, or the
// reader's message and exits 1.
#include "video_clip.hpp"

#include <cstdio>

int main(int argc, char** argv)
{
    if (argc != 2)
    {
        std::fprintf(stderr, "usage: dynblur_video_info VIDEO\n");
        return 2;
    }
    try
    {
        dynblur_samples::VideoClip clip;
        clip.open(argv[1], "VIDEO");
        cv::Mat image;
        double seconds = 0, first = 0;
        while (clip.read(image, seconds))
            first = clip.framesRead() == 1 ? seconds : first;
        std::printf("frames %d size %dx%d fps %.6g first %.6f last %.6f clock %s\n", clip.framesRead(),
                    clip.frameSize().width, clip.frameSize().height, clip.fps(), first, seconds,
                    clip.clockText().c_str());
        return 0;
    }
    catch (const cv::Exception& e)
    {
        std::fprintf(stderr, "error: %s\n", e.err.c_str());
        return 1;
    }
}
