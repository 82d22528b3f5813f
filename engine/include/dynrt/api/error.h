#pragma once
// The one exception type of the library API (dynrt/dynrt.h): every call that fails throws a
// dynrt::Error, whatever part of the engine found the problem, so an embedding program needs
// one catch clause. Nothing in the API aborts the process on bad input.

#include "dynrt/api/export.h"

#include <stdexcept>
#include <string>

namespace dynrt {

/// What every call of the library API throws when it fails: a code to act on and a one-line
/// message that names the mesh, the step and the value at fault where there is one.
class DYNRT_API Error : public std::runtime_error {
public:
    /// What kind of failure it is.
    enum class Code {
        /// A bad argument: an unknown or removed mesh id, a span of the wrong size, an index out
        /// of range, a non-finite value, a bad option. Nothing was changed.
        invalid_argument,
        /// Geometry that became unusable while updating (a vertex that is not finite, or not
        /// after transforming). The message names the mesh, the step and the vertex. Found
        /// before the trees are touched (the usual case), the engine keeps the trees of its
        /// last good update; found while a tree was built (a borrowed static or rigid buffer
        /// the caller wrote after handing it over), queries throw invalid_state until an
        /// update() succeeds.
        invalid_geometry,
        /// A call at the wrong time: tracing before the first update() or after an update()
        /// that failed half way, or a change while another thread is tracing.
        invalid_state,
    };

    /// An error of kind `code`, saying `message` (what(): one line, no trailing newline).
    Error(Code code, const std::string& message) : std::runtime_error(message), code_(code) {}
    /// What kind of failure it is.
    Code code() const noexcept { return code_; }

private:
    Code code_;
};

}  // namespace dynrt
