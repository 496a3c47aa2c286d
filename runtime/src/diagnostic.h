// Internal: filling a caller's Diagnostic without allocating.
#pragma once

#include "dng/status.h"

#include <cstdarg>

#if defined(__GNUC__) || defined(__clang__)
#define DNG_PRINTF_LIKE(format_index, first_arg) __attribute__((format(printf, format_index, first_arg)))
#else
#define DNG_PRINTF_LIKE(format_index, first_arg)
#endif

namespace dng {

/// Writes `status` and the formatted message into `diag` (when not null); returns `status`.
Status writeDiagnostic(Diagnostic* diag, Status status, const char* format, va_list args);
Status writeDiagnostic(Diagnostic* diag, Status status, const char* format, ...) DNG_PRINTF_LIKE(3, 4);
/// The same for a failure of docs/FORMAT.md rule `rule` ("V8"), which goes into diag->rule.
Status writeRuleDiagnostic(Diagnostic* diag, Status status, const char* rule, const char* format, va_list args);
Status writeRuleDiagnostic(Diagnostic* diag, Status status, const char* rule, const char* format, ...)
    DNG_PRINTF_LIKE(4, 5);

} // namespace dng
