// For the camera suites: how much of each pixel a colour patch covers, and
// masks of rectangles and of the pixels where two images differ.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace vssim::test {

// Where a patch of this colour lies in a camera image, weighted by how much
// of each pixel it covers: pixels whose channels the colour lacks are below
// 64 and whose others reach a quarter of their value (cv::inRange), each
// weighted by its smallest such channel over the colour's (anti-aliased
// edges are blends with the black body).
inline cv::Mat patchCoverage(const cv::Mat& frame, const cv::Vec3b& colour) {
    cv::Scalar lower, upper;
    for (int c = 0; c < 3; ++c) lower[c] = colour[c] / 4.0, upper[c] = colour[c] > 0 ? 255 : 63;
    cv::Mat mask;
    cv::inRange(frame, lower, upper, mask);
    cv::Mat coverage(frame.size(), CV_32F, cv::Scalar(1.0)), channels[3], channel;
    cv::split(frame, channels);
    for (int c = 0; c < 3; ++c) {
        if (colour[c] == 0) continue;
        channels[c].convertTo(channel, CV_32F, 1.0 / colour[c]);
        coverage = cv::min(coverage, channel);
    }
    coverage.setTo(0, ~mask);
    return coverage;
}

// The pixels any of these rectangles covers, as a mask (255 inside).
inline cv::Mat unionMask(cv::Size size, const std::vector<cv::Rect>& rects) {
    cv::Mat mask = cv::Mat::zeros(size, CV_8UC1);
    for (const cv::Rect& r : rects) mask(r).setTo(255);
    return mask;
}

// Pixels where two images differ, as a mask.
inline cv::Mat differenceMask(const cv::Mat& a, const cv::Mat& b) {
    cv::Mat diff, mask;
    cv::absdiff(a, b, diff);
    cv::transform(diff, mask, cv::Matx13f(1, 1, 1));
    return mask > 0;
}

}  // namespace vssim::test
