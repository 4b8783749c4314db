// The viewer's threads run at the lowest scheduling priority, so that on a busy robot the tracking
// and mapping threads always go first.
#pragma once

namespace ldsm::viewer {

/// Gives the calling thread the lowest priority (nice 19; Linux threads have their own nice
/// value). Does nothing where that is not possible.
void lowerThisThreadPriority();

}  // namespace ldsm::viewer
