#pragma once
/// \file input_error.h
/// Bad input that is not a scene-file problem: an unknown scene name, a malformed --vary or
/// --camera. Every verb turns it into exit code 2 with its message (main.cpp).

#include <stdexcept>

namespace ff::app {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace ff::app
