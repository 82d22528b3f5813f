#pragma once
// The one exception type of the library API (dynrt/dynrt.h): every call that fails throws a
// dynrt::Error, whatever part of the engine found the problem, so an embedding program needs
// one catch clause. Nothing in the API aborts the process on bad input.

#include "dynrt/api/export.h"

#include <stdexcept>
#include <string>

namespace dynrt {

class DYNRT_API Error : public std::runtime_error {
public:
    enum class Code {
        /// A bad argument: an unknown or removed mesh id, a span of the wrong size, an index out
        /// of range, a non-finite value, a bad option. Nothing was changed.
        invalid_argument,
        /// Geometry that became unusable while updating (a transform or vertex that is not
        /// finite after transforming). The message names the mesh and the step. The engine
        /// keeps the state of its last good update.
        invalid_geometry,
        /// A call at the wrong time: tracing before the first update(), or a change while
        /// another thread is tracing.
        invalid_state,
    };

    Error(Code code, const std::string& message) : std::runtime_error(message), code_(code) {}
    Code code() const noexcept { return code_; }

private:
    Code code_;
};

}  // namespace dynrt
