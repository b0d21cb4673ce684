// SPDX-License-Identifier: Apache-2.0
// The image's turn between consecutive frames (patch phase correlation per band of rows) and the
// features tracked across them (pyramidal Lucas–Kanade).
#include "precomp.hpp"

#include "refine/frame_motion.hpp"

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

// A patch whose phase-correlation peak is below this carries no shift (flat, or changed beyond recognition).
const double kMinResponse = 0.05;
// Patches are at least this tall and wide, analysis pixels.
const int kMinPatch = 48;
// A patch whose shift the band's turn misses by more than this, analysis pixels, is left out.
const double kMaxPatchResidual = 1.5;
// Tracks: at most this many, replenished below half of it, at least this far apart (analysis pixels).
const int kMaxTracks = 240;
const double kMinTrackSpacing = 10;
// A track is kept when the backward track returns within this, analysis pixels.
const float kBackTrackPx = 0.5f;
// Lucas–Kanade's window, analysis pixels, and pyramid levels: shifts of 40 px at 640 px wide.
const int kTrackWindow = 21, kTrackLevels = 3;

//! The frame as 8-bit luminance (sRGB-coded, as a video carries it) at `size`.
Mat analysisImage(const Mat& frame, const Size& size)
{
    Mat coded = frame;
    if (frame.depth() == CV_32F)
        linearToSrgb(frame, coded, CV_8U);
    Mat gray;
    if (coded.channels() == 1)
        gray = coded;
    else
        cvtColor(coded, gray, coded.channels() == 4 ? COLOR_BGRA2GRAY : COLOR_BGR2GRAY);
    if (gray.size() == size)
        return gray.clone();
    Mat reduced;
    resize(gray, reduced, size, 0, 0, INTER_AREA);
    return reduced;
}

/* The turn that best explains the patches' shifts (weighted least squares of the rotation flow); a
   patch more than `maxResidual` from it is left out and the rest fitted again. Two patches across
   the band decide the roll; one does not. */
bool fitTurn(std::vector<Vec3d>& du, std::vector<Vec3d>& dv, std::vector<Point2d>& shifts,
             std::vector<double>& weights, double maxResidual, Vec3d& turn, double& weight)
{
    for (;;)
    {
        if (shifts.size() < 2)
            return false;
        Matx33d normal = Matx33d::zeros();
        Vec3d rhs;
        weight = 0;
        for (size_t k = 0; k < shifts.size(); k++)
        {
            normal += weights[k] * (du[k] * du[k].t() + dv[k] * dv[k].t());
            rhs += weights[k] * (du[k] * shifts[k].x + dv[k] * shifts[k].y);
            weight += weights[k];
        }
        Mat solution;
        if (!solve(Mat(normal), Mat(rhs), solution, DECOMP_CHOLESKY))
            return false;
        turn = Vec3d(solution);
        size_t worst = 0;
        double worstResidual = -1;
        for (size_t k = 0; k < shifts.size(); k++)
        {
            const double residual = norm(Point2d(du[k].dot(turn), dv[k].dot(turn)) - shifts[k]);
            if (residual > worstResidual)
                worstResidual = residual, worst = k;
        }
        if (worstResidual <= maxResidual || shifts.size() == 2)
            return worstResidual <= maxResidual;
        du.erase(du.begin() + long(worst)), dv.erase(dv.begin() + long(worst));
        shifts.erase(shifts.begin() + long(worst)), weights.erase(weights.begin() + long(worst));
    }
}

}  // namespace

FrameMotionMeter::FrameMotionMeter(const Ptr<CameraModel>& camera, int analysisWidth) : camera_(camera)
{
    const Size full = camera->getImageSize();
    scale_ = std::min(1.0, double(analysisWidth) / full.width);
    analysisSize_ = Size(std::max(1, int(std::lround(full.width * scale_))),
                         std::max(1, int(std::lround(full.height * scale_))));
    scale_ = double(analysisSize_.width) / full.width;
}

Point2f FrameMotionMeter::toFull(const Point2f& p) const
{
    return Point2f(float((p.x + 0.5) / scale_ - 0.5), float((p.y + 0.5) / scale_ - 0.5));
}

void FrameMotionMeter::add(const Mat& frame, int index, bool follows, std::vector<BandTurn>* turns,
                           std::vector<TrackPair>& pairs)
{
    const Mat next = reduce(frame);
    if (follows && !previous_.empty())
    {
        if (turns)
            measureTurns(next, index, *turns);
        track(next, index, pairs);
    }
    else
    {
        points_.clear();
        anchors_.clear();
        anchorFrames_.clear();
    }
    // New tracks where there are too few, away from the ones kept.
    if (int(points_.size()) < kMaxTracks / 2)
    {
        Mat mask(next.size(), CV_8U, Scalar(255));
        for (const Point2f& p : points_)
            circle(mask, p, int(kMinTrackSpacing), Scalar(0), -1);
        std::vector<Point2f> corners;
        goodFeaturesToTrack(next, corners, kMaxTracks - int(points_.size()), 0.01, kMinTrackSpacing, mask);
        for (const Point2f& p : corners)
        {
            points_.push_back(p);
            anchors_.push_back(p);
            anchorFrames_.push_back(index);
        }
    }
    previous_ = next;
    previousIndex_ = index;
}

Mat FrameMotionMeter::reduce(const Mat& frame) const
{
    return analysisImage(frame, analysisSize_);
}

Rect FrameMotionMeter::patch(int band, int column) const
{
    const Size size = analysisSize_;
    const int width = size.width / kColumns, height = std::min(size.height, std::max(size.height / kBands, kMinPatch));
    const int top = std::min(size.height - height, std::max(0, int((band + 0.5) * size.height / kBands) - height / 2));
    return Rect(column * width, top, width, height);
}

std::vector<Point2d> FrameMotionMeter::patchCentres() const
{
    std::vector<Point2d> centres;
    for (int band = 0; band < kBands; band++)
        for (int column = 0; column < kColumns; column++)
        {
            const Rect from = patch(band, column);
            centres.emplace_back(toFull(Point2f(float(from.x + 0.5 * (from.width - 1)),
                                                float(from.y + 0.5 * (from.height - 1)))));
        }
    return centres;
}

std::vector<PatchShift> FrameMotionMeter::shifts(const Mat& previous, const Mat& next,
                                                 const std::vector<Point2d>& expected) const
{
    std::vector<PatchShift> patches;
    const Size size = analysisSize_;
    const Rect first = patch(0, 0);
    if (first.width < kMinPatch)
        return patches;
    Mat a, b, window;
    previous.convertTo(a, CV_32F);
    next.convertTo(b, CV_32F);
    Point2d global;
    if (expected.empty())
    {
        createHanningWindow(window, size, CV_32F);
        global = phaseCorrelate(a, b, window);
    }
    createHanningWindow(window, first.size(), CV_32F);
    const std::vector<Point2d> centres = patchCentres();
    for (int band = 0, k = 0; band < kBands; band++)
        for (int column = 0; column < kColumns; column++, k++)
        {
            const Rect from = patch(band, column);
            const Point2d guess = expected.empty() ? global : expected[size_t(k)] * scale_;
            const Rect to = from + Point(int(std::lround(std::min(1e6, std::max(-1e6, guess.x)))),
                                         int(std::lround(std::min(1e6, std::max(-1e6, guess.y)))));
            // Read within the frame: a patch whose content left it partly is still found where it overlaps.
            const Rect inside(std::min(size.width - to.width, std::max(0, to.x)),
                              std::min(size.height - to.height, std::max(0, to.y)), to.width, to.height);
            PatchShift p;
            const Point2d shift = phaseCorrelate(a(from), b(inside), window, &p.response) + Point2d(inside.tl() - from.tl());
            if (!(p.response >= kMinResponse))
                continue;
            p.index = k;
            p.band = band;
            p.centre = centres[size_t(k)];
            p.shift = shift * (1 / scale_);
            patches.push_back(p);
        }
    return patches;
}

void FrameMotionMeter::measureTurns(const Mat& next, int index, std::vector<BandTurn>& turns) const
{
    const std::vector<PatchShift> patches = shifts(previous_, next);
    const double fx = camera_->getFx(), fy = camera_->getFy(), cx = camera_->getCx(), cy = camera_->getCy();
    for (int band = 0; band < kBands; band++)
    {
        std::vector<Vec3d> du, dv;
        std::vector<Point2d> bandShifts;
        std::vector<double> weights;
        double row = 0;
        for (const PatchShift& p : patches)
        {
            if (p.band != band)
                continue;
            // The rotation flow at the patch's centre: d(shift)/d(rotation), pixels per radian.
            const double x = (p.centre.x - cx) / fx, y = (p.centre.y - cy) / fy;
            du.emplace_back(fx * x * y, -fx * (1 + x * x), fx * y);
            dv.emplace_back(fy * (1 + y * y), -fy * x * y, -fy * x);
            bandShifts.push_back(p.shift);
            weights.push_back(p.response);
            row = p.centre.y;
        }
        BandTurn t;
        if (!fitTurn(du, dv, bandShifts, weights, kMaxPatchResidual / scale_, t.turn, t.weight))
            continue;
        t.frameA = previousIndex_;
        t.frameB = index;
        t.row = row;
        turns.push_back(t);
    }
}

void FrameMotionMeter::track(const Mat& next, int index, std::vector<TrackPair>& pairs)
{
    if (points_.empty())
        return;
    std::vector<Point2f> forward, backward;
    std::vector<uchar> okForward, okBackward;
    std::vector<float> error;
    const TermCriteria stop(TermCriteria::COUNT | TermCriteria::EPS, 30, 0.01);
    calcOpticalFlowPyrLK(previous_, next, points_, forward, okForward, error, Size(kTrackWindow, kTrackWindow),
                         kTrackLevels, stop);
    calcOpticalFlowPyrLK(next, previous_, forward, backward, okBackward, error, Size(kTrackWindow, kTrackWindow),
                         kTrackLevels, stop);
    const Rect2f inside(1.f, 1.f, float(analysisSize_.width - 2), float(analysisSize_.height - 2));
    std::vector<Point2f> points, anchors;
    std::vector<int> anchorFrames;
    for (size_t k = 0; k < points_.size(); k++)
    {
        if (!okForward[k] || !okBackward[k] || norm(backward[k] - points_[k]) > kBackTrackPx ||
            !inside.contains(forward[k]))
            continue;
        TrackPair pair;
        pair.frameA = previousIndex_;
        pair.frameB = index;
        pair.a = toFull(points_[k]);
        pair.b = toFull(forward[k]);
        pairs.push_back(pair);
        Point2f anchor = anchors_[k];
        int anchorFrame = anchorFrames_[k];
        if (index - anchorFrame >= kAnchorSpan)
        {
            pair.frameA = anchorFrame;
            pair.a = toFull(anchor);
            pairs.push_back(pair);
            anchor = forward[k], anchorFrame = index;
        }
        points.push_back(forward[k]);
        anchors.push_back(anchor);
        anchorFrames.push_back(anchorFrame);
    }
    points_.swap(points);
    anchors_.swap(anchors);
    anchorFrames_.swap(anchorFrames);
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
