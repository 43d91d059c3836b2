#pragma once
/// \file portable_math.h
/// \brief Sine and cosine with the same bits on every machine.
///
/// The C library's `sin`/`cos` differ in the last bit between implementations (glibc,
/// musl, Apple, MSVC), which is enough to break the promise that a plant seed gives a
/// bit-identical mesh everywhere. These functions use only IEEE-754 +, -, * and floor,
/// whose results the standard fixes, so they give the same bits wherever the compiler
/// does not fuse multiply-adds (src/portable_math.cpp is built with -ffp-contract=off).

namespace plantnbv {

/// \brief sin(x) and cos(x) of an angle in radians, accurate to about 2 ulp for
/// |x| < 1e5 (Cody-Waite reduction by pi/2, fdlibm's polynomial kernels). NaN for
/// non-finite x. Thread-safe.
void portableSinCos(double x_rad, double& sin_x, double& cos_x);

/// \brief sin(x) of an angle in radians; see portableSinCos.
double portableSin(double x_rad);

/// \brief cos(x) of an angle in radians; see portableSinCos.
double portableCos(double x_rad);

} // namespace plantnbv
