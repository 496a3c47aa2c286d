// Status descriptions and diagnostic formatting.
#include "diagnostic.h"

#include <cstdio>

namespace dng {

const char* statusString(Status status) {
  switch (status) {
  case Status::kOk: return "ok";
  case Status::kInvalidArgument: return "invalid argument";
  case Status::kIoError: return "I/O error";
  case Status::kUnsupportedHost: return "unsupported host (big-endian)";
  case Status::kTruncated: return "file truncated";
  case Status::kTrailingBytes: return "trailing bytes after the end of the file";
  case Status::kBadMagic: return "not a .dng file (bad magic)";
  case Status::kUnsupportedVersion: return "unsupported format version";
  case Status::kBadHeader: return "malformed header";
  case Status::kHeaderHashMismatch: return "header hash mismatch";
  case Status::kBadSectionTable: return "malformed section table";
  case Status::kSectionTableHashMismatch: return "section table hash mismatch";
  case Status::kSectionOutOfBounds: return "section outside the file";
  case Status::kSectionMisaligned: return "section not 64-byte aligned";
  case Status::kSectionOverlap: return "sections overlap or are out of order";
  case Status::kUnknownRequiredSection: return "unknown required section";
  case Status::kDuplicateSection: return "duplicate section";
  case Status::kMissingSection: return "missing section";
  case Status::kBadGrid: return "invalid grid geometry";
  case Status::kUnsupportedEncoding: return "unsupported encoding";
  case Status::kBadPayloadSize: return "payload size does not match the grid";
  case Status::kBadTileEntry: return "invalid brick-top entry";
  case Status::kBadValue: return "non-finite or out-of-range value in the payload";
  case Status::kSectionHashMismatch: return "section hash mismatch";
  case Status::kOutOfMemory: return "out of memory";
  case Status::kNonZeroPadding: return "non-zero padding between sections";
  }
  return "unknown status";
}

Status writeDiagnostic(Diagnostic* diag, Status status, const char* format, va_list args) {
  if (diag == nullptr) return status;
  diag->status = status;
  diag->rule[0] = '\0'; // no rule unless writeRuleDiagnostic names one
  std::vsnprintf(diag->message, sizeof diag->message, format, args);
  return status;
}

Status writeRuleDiagnostic(Diagnostic* diag, Status status, const char* rule, const char* format, va_list args) {
  if (diag == nullptr) return status;
  writeDiagnostic(diag, status, format, args);
  std::snprintf(diag->rule, sizeof diag->rule, "%s", rule);
  return status;
}

Status writeRuleDiagnostic(Diagnostic* diag, Status status, const char* rule, const char* format, ...) {
  va_list args;
  va_start(args, format);
  writeRuleDiagnostic(diag, status, rule, format, args);
  va_end(args);
  return status;
}

Status writeDiagnostic(Diagnostic* diag, Status status, const char* format, ...) {
  va_list args;
  va_start(args, format);
  writeDiagnostic(diag, status, format, args);
  va_end(args);
  return status;
}

} // namespace dng
