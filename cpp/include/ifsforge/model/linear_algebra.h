#pragma once
/// @file Dense linear algebra on matrices of at most kMaxDim x kMaxDim; internal to the model.
#include <array>

#include "ifsforge/model/affine_map.h"

namespace ifsforge::la {

using Matrix = std::array<std::array<double, kMaxDim>, kMaxDim>;

/// @brief The leading k x k block of a map's linear part.
Matrix block(const AffineMap& map, int k);
/// @brief Gauss-Jordan with partial pivoting; false when (numerically) singular.
bool invert(const Matrix& m, int n, Matrix& out);
double determinant(Matrix m, int n);
/// @brief Largest singular value: sqrt of the largest eigenvalue of M^T M (Jacobi sweeps).
double spectral_norm(const Matrix& m, int n);
/// @brief M = Q R with Q a rotation (det +1) and R upper triangular, its diagonal
/// non-negative except perhaps the last entry, which carries a reflection (Householder).
void qr(const Matrix& m, int n, Matrix& q, Matrix& r);

}  // namespace ifsforge::la
