// Status codes of the runtime. Nothing in the runtime throws or aborts on bad data: every call that
// can fail returns one of these, and may fill a caller-supplied Diagnostic with a message.
#pragma once

#include <cstdint>

namespace dng {

/// Stable numeric values: they are part of the C ABI and of dngdump's findings.
enum class Status : std::int32_t {
  kOk = 0,
  kInvalidArgument = 1,    ///< null pointer, misaligned buffer, bad option
  kIoError = 2,            ///< the file could not be opened, sized or mapped
  kUnsupportedHost = 3,    ///< big-endian host
  kTruncated = 4,          ///< fewer bytes than the header says the file has
  kTrailingBytes = 5,      ///< more bytes than the header says the file has
  kBadMagic = 6,           ///< not a .dng file, or damaged by a text-mode transfer
  kUnsupportedVersion = 7, ///< major version newer than this reader (or zero)
  kBadHeader = 8,          ///< header size or layout fields are wrong
  kHeaderHashMismatch = 9, ///< header bytes changed after writing
  kBadSectionTable = 10,   ///< table offset, count or alignment out of rules
  kSectionTableHashMismatch = 11,
  kSectionOutOfBounds = 12,     ///< a section's offset + size leaves the file (overflow-safe)
  kSectionMisaligned = 13,      ///< a section offset is not 64-byte aligned
  kSectionOverlap = 14,         ///< sections overlap, are unsorted or sit inside the table
  kUnknownRequiredSection = 15, ///< a section flagged required that this reader does not know
  kDuplicateSection = 16,
  kMissingSection = 17,      ///< GRID or the payload for the grid's encoding is absent
  kBadGrid = 18,             ///< non-finite or non-positive geometry, zero dimensions
  kUnsupportedEncoding = 19, ///< unknown encoding or brick size
  kBadPayloadSize = 20,      ///< payload section size does not match the grid
  kBadTileEntry = 21,        ///< brick index out of range, reserved bits set, bad plane value
  kBadValue = 22,            ///< a dense voxel holds NaN, infinity, |d| > 1e18 or a normal longer than 1
  kSectionHashMismatch = 23, ///< a section's bytes do not match its hash (verifyHashes only)
  kOutOfMemory = 24,
  kNonZeroPadding = 25, ///< a byte between sections is not zero (verifyHashes only)
};

/// Short, static English description of a status ("ok", "file truncated", ...). Never null.
const char* statusString(Status status);

/// Caller-owned place for the message of a failed call: the status, the docs/FORMAT.md rule that
/// failed as a stable machine-readable ID ("V8"; V2 for a null or misaligned buffer; empty when the failure breaks no
/// file rule, such as a bad argument), and a NUL-terminated sentence with the numbers involved. Fixed size so filling
/// it never allocates.
struct Diagnostic {
  Status status = Status::kOk;
  char rule[8] = {};
  char message[256] = {};
};

} // namespace dng
