#pragma once
/// \file counted_scalar.h
/// A double that counts its floating-point operations, so a kernel templated on its scalar can
/// report how many flops one evaluation does (`flexframe bench --solve`, cb_shell.md "Flop
/// count"). One add, subtract, multiply, divide or square root is one flop, as in the usual
/// convention (a fused multiply-add is two); negation, copies and comparisons are free.

#include <Eigen/Core>
#include <cmath>
#include <cstdint>

namespace ff::shell {

/// The running count of the calling thread; reset it before the kernel, read it after.
inline thread_local std::int64_t counted_flops = 0;

struct CountedDouble {
  double value = 0.0;
  CountedDouble() = default;
  CountedDouble(double v) : value(v) {}  // NOLINT: literals in kernel code promote silently

  CountedDouble& operator+=(CountedDouble b) { return ++counted_flops, value += b.value, *this; }
  CountedDouble& operator-=(CountedDouble b) { return ++counted_flops, value -= b.value, *this; }
  CountedDouble& operator*=(CountedDouble b) { return ++counted_flops, value *= b.value, *this; }
  CountedDouble& operator/=(CountedDouble b) { return ++counted_flops, value /= b.value, *this; }
  friend CountedDouble operator+(CountedDouble a, CountedDouble b) { return a += b; }
  friend CountedDouble operator-(CountedDouble a, CountedDouble b) { return a -= b; }
  friend CountedDouble operator*(CountedDouble a, CountedDouble b) { return a *= b; }
  friend CountedDouble operator/(CountedDouble a, CountedDouble b) { return a /= b; }
  friend CountedDouble operator-(CountedDouble a) { return CountedDouble(-a.value); }
  friend CountedDouble operator+(CountedDouble a) { return a; }
  friend bool operator<(CountedDouble a, CountedDouble b) { return a.value < b.value; }
  friend bool operator>(CountedDouble a, CountedDouble b) { return a.value > b.value; }
  friend bool operator<=(CountedDouble a, CountedDouble b) { return a.value <= b.value; }
  friend bool operator>=(CountedDouble a, CountedDouble b) { return a.value >= b.value; }
  friend bool operator==(CountedDouble a, CountedDouble b) { return a.value == b.value; }
  friend bool operator!=(CountedDouble a, CountedDouble b) { return a.value != b.value; }
};

inline CountedDouble sqrt(CountedDouble a) { return ++counted_flops, CountedDouble(std::sqrt(a.value)); }
inline CountedDouble abs(CountedDouble a) { return CountedDouble(std::abs(a.value)); }
inline CountedDouble conj(CountedDouble a) { return a; }
inline CountedDouble real(CountedDouble a) { return a; }
inline CountedDouble imag(CountedDouble) { return CountedDouble(0.0); }
inline CountedDouble abs2(CountedDouble a) { return a * a; }
inline bool isfinite(CountedDouble a) { return std::isfinite(a.value); }

}  // namespace ff::shell

namespace Eigen {
// Eigen's requirements for a custom real scalar (its "Using custom scalar types" page)
template <>
struct NumTraits<ff::shell::CountedDouble> : NumTraits<double> {
  using Real = ff::shell::CountedDouble;
  using NonInteger = ff::shell::CountedDouble;
  using Nested = ff::shell::CountedDouble;
  using Literal = ff::shell::CountedDouble;
  enum { IsComplex = 0, IsInteger = 0, IsSigned = 1, RequireInitialization = 1, ReadCost = 1, AddCost = 1, MulCost = 1 };
};
}  // namespace Eigen
