// The allowed range of a numeric configuration field (config.h's visit() schema).
#pragma once

namespace ldsm {

/// Inclusive range of allowed values of a numeric field.
template <typename T>
struct Range {
  T min;
  T max;
};

}  // namespace ldsm
