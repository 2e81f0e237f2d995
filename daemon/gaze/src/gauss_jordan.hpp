// Small dense linear solves shared by the gaze chain's fits (calibration polynomial, landing
// late correction): Gauss-Jordan elimination with partial pivoting, in place.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

namespace fovea::gaze::detail {

// Solves A X = B for an augmented N x (N + R) matrix [A | B]; on success columns N.. hold X.
// False when a pivot is below 1e-12 of A's largest entry (near singular).
template <int N, int R>
bool gauss_jordan(double (&m)[N][N + R]) {
    double scale = 0.0;
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) scale = std::max(scale, std::fabs(m[i][j]));
    for (int col = 0; col < N; ++col) {
        int piv = col;
        for (int r = col + 1; r < N; ++r)
            if (std::fabs(m[r][col]) > std::fabs(m[piv][col])) piv = r;
        if (std::fabs(m[piv][col]) < 1e-12 * std::max(1.0, scale)) return false;
        for (int j = 0; j < N + R; ++j) std::swap(m[col][j], m[piv][j]);
        for (int r = 0; r < N; ++r) {
            if (r == col) continue;
            const double f = m[r][col] / m[col][col];
            for (int j = col; j < N + R; ++j) m[r][j] -= f * m[col][j];
        }
    }
    for (int i = 0; i < N; ++i)
        for (int j = N; j < N + R; ++j) m[i][j] /= m[i][i];
    return true;
}

}  // namespace fovea::gaze::detail
