// SPDX-License-Identifier: Apache-2.0
// dynblur_restore_video on a recording whose motion is the plant's response to its command log:
// streamed through ReferencePairing, each frame restored (FrameRestorer) and written to the video,
// the CSV, the contact sheet and, with --truth, measured; then the summary.
#include "restore_video.hpp"

#include "atomic_file.hpp"  // samples/support
#include "contact_sheet.hpp"
#include "frame_timing.hpp"  // samples/simulation
#include "frame_restorer.hpp"
#include "recording.hpp"
#include "reference_pairing.hpp"
#include "restored_video.hpp"
#include "truth.hpp"

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <stdexcept>

namespace dynblur_samples {

using namespace cv;
using namespace cv::dynblur;

namespace {

const size_t kSheetRows = 6;

//! --no-still-after and --unobserved, checked before any file is opened.
struct StreamSettings
{
    bool unrefinedUnchanged = false;
    int unobserved = UNOBSERVED_RECORDED;

    explicit StreamSettings(const CliArgs& args)
    {
        const std::string noStillAfter = args.str("no-still-after");
        if (noStillAfter != "as-told" && noStillAfter != "unchanged")
            throw std::runtime_error("--no-still-after must be as-told or unchanged");
        unrefinedUnchanged = noStillAfter == "unchanged";
        const std::string name = args.str("unobserved");
        unobserved = name == "recorded" ? UNOBSERVED_RECORDED
                     : name == "marked" ? UNOBSERVED_MARKED
                     : name == "nearest" ? UNOBSERVED_NEAREST : -1;
        if (unobserved < 0)
            throw std::runtime_error("--unobserved must be recorded, marked or nearest");
    }
};

//! The moving frames' count, refusals and the most blurred, and the frames that could not be refined.
struct RecordingSummary
{
    int moving = 0, refused = 0, mostBlurred = -1;
    double mostBlurPx = -1;
    std::vector<int> unrefined;

    void add(const RestoredFrame& r, int frame)
    {
        if (r.noStillAfter)
            unrefined.push_back(frame);
        moving++;
        refused += !r.correction.applied;
        if (r.blurPx > mostBlurPx)
            mostBlurPx = r.blurPx, mostBlurred = frame;
    }

    void print(bool unrefinedUnchanged) const
    {
        if (!unrefined.empty())
        {
            std::string list;
            for (int frame : unrefined)
                list += (list.empty() ? "" : ", ") + std::to_string(frame);
            std::printf("could not refine %zu frame(s) with no still after their move: %s; %s (--no-still-after)\n",
                        unrefined.size(), list.c_str(),
                        unrefinedUnchanged ? "written as recorded" : "restored as told");
        }
        std::printf("%d moving frame(s): %d restored, %d refused (%.0f %%); the most blurred is frame %d (%.1f px)\n",
                    moving, moving - refused, refused, moving ? 100.0 * refused / moving : 0.0, mostBlurred,
                    mostBlurPx);
    }
};

//! One line of the CSV (kFrameCsvHeader); `truthColumns` ",,," without a truth.
std::string csvRow(const ReferencePairing::Item& item, const RestoredFrame& r, const std::string& truthColumns)
{
    return frameCsvColumns(item.record.frame, item.still ? "still" : exposureWindowName(r.window),
                           !item.still && r.correction.applied, r.correction,
                           item.still ? std::string("still") : r.correction.reason,
                           item.still ? "still" : exposureWindowName(item.window), r.blurPx) +
           "," + truthColumns + "\n";
}

//! The frame's window for the contact sheet, with the window as told where the refinement changed it.
std::string windowLabel(int window, int asTold)
{
    return window == asTold ? std::string(exposureWindowName(window))
                            : format("%s (as told %s)", exposureWindowName(window), exposureWindowName(asTold));
}

//! The deblurrer for the recording: the preset and model, the refinement, the fill, the calibration.
Ptr<DynamicDeblurrer> createDeblurrer(const OpenedRecording& recording, const RestorationSettings& settings,
                                      const StreamSettings& stream, int refinement,
                                      const MotionCorrection* calibration)
{
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(recording.plant, recording.camera);
    settings.apply(*deblurrer);
    deblurrer->setRefinement(refinement);
    deblurrer->setUnobservedFill(stream.unobserved);
    if (calibration)
        deblurrer->setCalibration(*calibration);
    return deblurrer;
}

}  // namespace

int restoreCommandedRecording(const CliArgs& args, const RestorationSettings& settings)
{
    const StreamSettings stream(args);
    const std::string videoOut = args.str("out"), csvOut = args.str("csv", pathStem(videoOut) + ".csv");
    OpenedRecording recording;
    OpenedRecording::open(args, defaultCameraPath(), recording);
    const std::vector<FrameRecord>& log = recording.log;
    const bool calibrated = !recording.timingPath.empty();
    int refinement = 0;
    if (!parseRefinementList(args.str("refine", calibrated ? "offset" : "all"), REFINE_ALL, refinement))
        throw std::runtime_error("--refine takes offset, line-delay, plant, all or none, comma-separated");
    const MotionCorrection calibration =
        calibrated ? TimingCalibration::load(recording.timingPath).correction : MotionCorrection();
    std::unique_ptr<TruthComparison> truth;
    if (args.has("truth"))
        truth.reset(new TruthComparison(args.str("truth"), recording.commanded(), recording.camera));
    const Ptr<DynamicDeblurrer> deblurrer =
        createDeblurrer(recording, settings, stream, refinement, calibrated ? &calibration : nullptr);

    const Size size = recording.camera->getImageSize();
    const double fps =
        log.size() > 1 ? (log.size() - 1) / (log.back().frameStart - log.front().frameStart) : 30.0;
    RestoredVideo video(videoOut, csvOut, fps, size, std::string(kFrameCsvHeader) + "\n");
    ReferencePairing pairing(recording.commanded(), recording.camera, recording.commands, calibration, 0.005);
    ProgressLine progress(pairing, log.size(), int(std::count_if(log.begin(), log.end(), [&](const FrameRecord& f) {
                                                   return !pairing.isStill(f, size.height);
                                               })));
    FrameRestorer restorer(deblurrer, recording.commanded(), recording.camera, calibration, stream.unrefinedUnchanged);
    ContactSheet sheet(kSheetRows);  // the most blurred moving frames, blurred beside restored, for a look
    RecordingSummary summary;
    const auto restoreAndWrite = [&](const std::vector<ReferencePairing::Item>& ready) {
        for (const ReferencePairing::Item& item : ready)
        {
            const RestoredFrame r = restorer.restore(item, progress);
            std::string truthColumns = ",,,", gainText;
            if (!item.still)
                summary.add(r, item.record.frame);
            if (!item.still && truth)
                truth->measure(item, r, truthColumns, gainText);
            if (!item.still && r.window != EXPOSURE_IV)
                sheet.offer(item.image, r.image, item.record.frame, windowLabel(r.window, item.window), r.blurPx,
                            r.correction, gainText);
            video.write(r.image);
            video.csv() << csvRow(item, r, truthColumns);
            progress.frameWritten();
        }
        progress.show("");
    };
    for (const FrameRecord& f : log)
        restoreAndWrite(pairing.push(f, recording.read(f).clone()));
    restoreAndWrite(pairing.finish());
    std::printf("\n");
    summary.print(stream.unrefinedUnchanged);
    if (truth)
        truth->printSummary(summary.mostBlurred, summary.refused);

    video.close();
    const std::string sheetPath = pathStem(videoOut) + "_frames.png";
    if (!sheet.empty() && !imwrite(video.temporaryFor(sheetPath), sheet.render()))
        CV_Error(Error::StsError, "cannot write '" + sheetPath + "'");
    video.commit();
    const std::string sheetNote =
        sheet.empty() ? "" : " and " + sheetPath + " (the most blurred moving frames: recorded | restored)";
    std::printf("wrote %s, %s%s\n", videoOut.c_str(), csvOut.c_str(), sheetNote.c_str());
    return 0;
}

}  // namespace dynblur_samples
