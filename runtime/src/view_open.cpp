// View::open: the one validation pass (docs/FORMAT.md §6, rules V1-V16 and V19-V22). After it succeeds, every
// offset, size and brick index the query path uses is known to be in range, and every float it
// reads is finite, so queries need no checks beyond clamping the position.
#include "diagnostic.h"
#include "dng/format/codec.h"
#include "dng/format/limits.h"
#include "dng/format/xxhash64.h"
#include "dng/view.h"

#include <cmath>
#include <cstring>

namespace dng {

namespace fmt = format;

namespace {

bool saneLength(float x) { return std::fabs(x) <= fmt::kMaxMagnitude; } // false for NaN too

// dims[0] * dims[1] * dims[2] into *out_product when it is at most `limit` (no overflow possible:
// each factor is checked against what is left of the limit).
bool productAtMost(const std::uint32_t dims[3], std::uint64_t limit, std::uint64_t* out_product) {
  std::uint64_t product = 1;
  for (int a = 0; a < 3; ++a) {
    if (dims[a] != 0 && product > limit / dims[a]) return false;
    product *= dims[a];
  }
  *out_product = product;
  return true;
}

} // namespace

class ViewBuilder {
public:
  ViewBuilder(const std::uint8_t* data, std::size_t size, Diagnostic* diag) : data_(data), size_(size), diag_(diag) {}

  Status run(View* out) {
    Status s = checkHeader();
    if (s == Status::kOk) s = checkTable();
    if (s == Status::kOk) s = checkSections();
    if (s == Status::kOk) s = checkGrid();
    if (s == Status::kOk) s = grid_.encoding == fmt::Encoding::kDense ? checkDense() : checkBricked();
    if (s == Status::kOk) s = checkLift();
    if (s == Status::kOk) s = checkWordNormals(gradient_section_, "V20", false, &view_.gradient_);
    if (s == Status::kOk) s = checkWordNormals(shading_section_, "V21", true, &view_.shading_);
    if (s == Status::kOk) s = checkSecondPlanes();
    if (s != Status::kOk) return s;
    view_.data_ = data_;
    view_.size_ = size_;
    *out = view_;
    return Status::kOk;
  }

private:
  struct Found {
    bool present = false;
    fmt::SectionEntry copy{};
  };

  Status fail(Status status, const char* rule, const char* format, ...) DNG_PRINTF_LIKE(4, 5);

  const std::uint8_t* at(std::uint64_t offset) const { return data_ + offset; }

  // V1-V8: host, buffer, magic, version, header hash, header fields, file size.
  Status checkHeader() {
    if (!fmt::isLittleEndianHost()) return fail(Status::kUnsupportedHost, "V1", "host is big-endian");
    if (data_ == nullptr) return fail(Status::kInvalidArgument, "V2", "no bytes given");
    if (reinterpret_cast<std::uintptr_t>(data_) % 8 != 0)
      return fail(Status::kInvalidArgument, "V2", "buffer address must be 8-byte aligned");
    if (size_ < fmt::kHeaderSize)
      return fail(Status::kTruncated, "V3", "%zu bytes is shorter than the %u-byte header", size_, fmt::kHeaderSize);
    std::memcpy(&header_, data_, sizeof header_);
    if (std::memcmp(header_.magic, fmt::kMagic, sizeof fmt::kMagic) != 0)
      return fail(Status::kBadMagic, "V4", "magic bytes are not those of a .dng file");
    if (header_.version_major != fmt::kVersionMajor)
      return fail(Status::kUnsupportedVersion, "V5", "format version %u.%u, this reader reads major version %u",
                  header_.version_major, header_.version_minor, fmt::kVersionMajor);
    if (fmt::xxhash64(data_, offsetof(fmt::FileHeader, header_hash)) != header_.header_hash)
      return fail(Status::kHeaderHashMismatch, "V6", "header hash does not match the header bytes");
    if (header_.header_size != fmt::kHeaderSize)
      return fail(Status::kBadHeader, "V7", "header size %u, expected %u", header_.header_size, fmt::kHeaderSize);
    if (header_.file_size > size_)
      return fail(Status::kTruncated, "V8", "file is truncated: header says %llu bytes, %zu present",
                  (unsigned long long)header_.file_size, size_);
    if (header_.file_size < size_)
      return fail(Status::kTrailingBytes, "V8", "%zu bytes present, header says the file ends at %llu", size_,
                  (unsigned long long)header_.file_size);
    view_.version_major_ = header_.version_major;
    view_.version_minor_ = header_.version_minor;
    return Status::kOk;
  }

  // V9: the table itself.
  Status checkTable() {
    const std::uint64_t offset = header_.section_table_offset;
    if (header_.section_count > fmt::kMaxSections)
      return fail(Status::kBadSectionTable, "V9", "%u sections, at most %u allowed", header_.section_count,
                  fmt::kMaxSections);
    if (offset < fmt::kHeaderSize || offset % fmt::kSectionAlignment != 0 || offset > size_ ||
        std::uint64_t(header_.section_count) * sizeof(fmt::SectionEntry) > size_ - offset)
      return fail(Status::kBadSectionTable, "V9", "section table at %llu with %u entries does not fit the file",
                  (unsigned long long)offset, header_.section_count);
    table_end_ = offset + std::uint64_t(header_.section_count) * sizeof(fmt::SectionEntry);
    if (fmt::xxhash64(at(offset), table_end_ - offset) != header_.section_table_hash)
      return fail(Status::kSectionTableHashMismatch, "V9", "section table hash does not match");
    return Status::kOk;
  }

  // V10-V11: every entry in bounds, aligned, sorted, disjoint; tags known or optional; no twins.
  Status checkSections() {
    std::uint64_t previous_end = table_end_;
    for (std::uint32_t s = 0; s < header_.section_count; ++s) {
      fmt::SectionEntry e;
      std::memcpy(&e, at(header_.section_table_offset + s * sizeof e), sizeof e);
      if (e.offset % fmt::kSectionAlignment != 0)
        return fail(Status::kSectionMisaligned, "V10", "section %u starts at %llu, not a multiple of 64", s,
                    (unsigned long long)e.offset);
      if (e.offset > size_ || e.size > size_ - e.offset)
        return fail(Status::kSectionOutOfBounds, "V10", "section %u (offset %llu, size %llu) leaves the %zu-byte file",
                    s, (unsigned long long)e.offset, (unsigned long long)e.size, size_);
      if (e.offset < previous_end)
        return fail(Status::kSectionOverlap, "V10", "section %u at %llu overlaps the table or the previous section", s,
                    (unsigned long long)e.offset);
      previous_end = e.offset + e.size;
      const Status known = recordSection(s, e);
      if (known != Status::kOk) return known;
    }
    return Status::kOk;
  }

  Status recordSection(std::uint32_t index, const fmt::SectionEntry& e) {
    Found* slot = slotFor(e.tag);
    if (slot == nullptr) {
      if (e.flags & fmt::kSectionRequired)
        return fail(Status::kUnknownRequiredSection, "V11", "section %u has unknown tag '%.4s' and is marked required",
                    index, reinterpret_cast<const char*>(&e.tag));
      return Status::kOk; // unknown optional sections are ignored by design
    }
    if (slot->present)
      return fail(Status::kDuplicateSection, "V11", "tag '%.4s' appears twice", reinterpret_cast<const char*>(&e.tag));
    slot->present = true;
    slot->copy = e;
    return Status::kOk;
  }

  Found* slotFor(std::uint32_t tag) {
    switch (tag) {
    case fmt::kTagGrid: return &grid_section_;
    case fmt::kTagMetadata: return &meta_section_;
    case fmt::kTagDense: return &dense_section_;
    case fmt::kTagBrickTop: return &top_section_;
    case fmt::kTagBrickPool: return &pool_section_;
    case fmt::kTagLift: return &lift_section_;
    case fmt::kTagGradient: return &gradient_section_;
    case fmt::kTagShading: return &shading_section_;
    case fmt::kTagSecondPlanes: return &second_section_;
    default: return nullptr;
    }
  }

  Status checkGrid();
  Status checkDense();
  Status checkBricked();
  Status checkTopEntries(std::uint64_t pool_bricks);
  Status checkLift();
  Status checkWordNormals(const Found& section, const char* rule, bool padded, const std::uint16_t** out);
  Status checkSecondPlanes();

  const std::uint8_t* data_;
  std::size_t size_;
  Diagnostic* diag_;
  fmt::FileHeader header_{};
  std::uint64_t table_end_ = 0;
  Found grid_section_, meta_section_, dense_section_, top_section_, pool_section_, lift_section_, gradient_section_,
      shading_section_, second_section_;
  GridInfo grid_;
  View view_;
};

Status ViewBuilder::fail(Status status, const char* rule, const char* format, ...) {
  va_list args;
  va_start(args, format);
  writeRuleDiagnostic(diag_, status, rule, format, args);
  va_end(args);
  return status;
}

// V12-V13: geometry and encoding.
Status ViewBuilder::checkGrid() {
  if (!grid_section_.present) return fail(Status::kMissingSection, "V12", "no GRID section");
  if (grid_section_.copy.size < sizeof(fmt::GridSection))
    return fail(Status::kBadPayloadSize, "V12", "GRID section has %llu bytes, needs %zu",
                (unsigned long long)grid_section_.copy.size, sizeof(fmt::GridSection));
  fmt::GridSection g;
  std::memcpy(&g, at(grid_section_.copy.offset), sizeof g);
  if (!saneLength(g.origin[0]) || !saneLength(g.origin[1]) || !saneLength(g.origin[2]))
    return fail(Status::kBadGrid, "V12", "grid origin is not finite or beyond 1e18");
  if (!(g.voxel_size > 0.0f) || !saneLength(g.voxel_size) || !saneLength(1.0f / g.voxel_size))
    return fail(Status::kBadGrid, "V12", "voxel size %g is not in [1e-18, 1e18]", double(g.voxel_size));
  if (!(g.band > 0.0f) || !saneLength(g.band))
    return fail(Status::kBadGrid, "V12", "band %g is not in (0, 1e18]", double(g.band));
  for (int a = 0; a < 3; ++a) {
    if (g.dims[a] == 0 || g.dims[a] > fmt::kMaxAxisVoxels)
      return fail(Status::kBadGrid, "V12", "dimension %d is %u, must be 1..%u", a, g.dims[a], fmt::kMaxAxisVoxels);
  }
  if (g.encoding > std::uint32_t(fmt::Encoding::kBricked))
    return fail(Status::kUnsupportedEncoding, "V13", "encoding %u is unknown", g.encoding);
  grid_.origin = {g.origin[0], g.origin[1], g.origin[2]};
  grid_.voxel_size = g.voxel_size;
  for (int a = 0; a < 3; ++a)
    grid_.dims[a] = g.dims[a];
  grid_.band = g.band;
  grid_.encoding = fmt::Encoding(g.encoding);
  grid_.flags = g.flags; // 1.0 writers wrote 0 here; unknown bits are for later minor versions
  if (grid_.encoding == fmt::Encoding::kBricked) {
    if (g.brick_log2 < 2 || g.brick_log2 > 4)
      return fail(Status::kUnsupportedEncoding, "V13", "brick edge 2^%u, must be 4, 8 or 16", g.brick_log2);
    grid_.brick_size = 1u << g.brick_log2;
    for (int a = 0; a < 3; ++a) {
      const std::uint32_t expected = (g.dims[a] + grid_.brick_size - 1) >> g.brick_log2;
      if (g.brick_dims[a] != expected)
        return fail(Status::kBadGrid, "V13", "brick dimension %d is %u, expected %u", a, g.brick_dims[a], expected);
      grid_.brick_dims[a] = expected;
    }
    grid_.tolerance_distance = g.tolerance_distance;
    grid_.tolerance_normal_deg = g.tolerance_normal_deg;
    view_.brick_log2_ = g.brick_log2;
  }
  view_.grid_ = grid_;
  view_.inv_voxel_size_ = 1.0f / g.voxel_size;
  view_.range_step_ = fmt::rangeStep(g.band);
  for (int a = 0; a < 3; ++a)
    view_.dims_f_[a] = float(g.dims[a]);
  if (meta_section_.present)
    view_.metadata_ = {reinterpret_cast<const char*>(at(meta_section_.copy.offset)), meta_section_.copy.size};
  return Status::kOk;
}

// V14: dense payload size and finiteness.
Status ViewBuilder::checkDense() {
  if (!dense_section_.present) return fail(Status::kMissingSection, "V14", "dense grid without DENS section");
  std::uint64_t voxels = 0;
  if (!productAtMost(grid_.dims, size_ / sizeof(fmt::DenseVoxel), &voxels) ||
      dense_section_.copy.size != voxels * sizeof(fmt::DenseVoxel))
    return fail(Status::kBadPayloadSize, "V14", "DENS has %llu bytes, the grid needs %llu voxels of 16 bytes",
                (unsigned long long)dense_section_.copy.size, (unsigned long long)voxels);
  const auto* voxel = reinterpret_cast<const fmt::DenseVoxel*>(at(dense_section_.copy.offset));
  for (std::uint64_t v = 0; v < voxels; ++v) {
    const fmt::DenseVoxel& x = voxel[v];
    const float n2 = x.normal[0] * x.normal[0] + x.normal[1] * x.normal[1] + x.normal[2] * x.normal[2];
    if (!saneLength(x.distance) || !(n2 <= fmt::kMaxNormalLengthSquared))
      return fail(Status::kBadValue, "V14", "dense voxel %llu holds a non-finite or out-of-range value",
                  (unsigned long long)v);
  }
  view_.dense_ = voxel;
  return Status::kOk;
}

// V15: top table and pool sizes; V16: every top entry.
Status ViewBuilder::checkBricked() {
  if (!top_section_.present || !pool_section_.present)
    return fail(Status::kMissingSection, "V15", "bricked grid without BTOP and BPOL sections");
  std::uint64_t tiles = 0;
  if (!productAtMost(grid_.brick_dims, size_ / 8, &tiles) || top_section_.copy.size != tiles * 8)
    return fail(Status::kBadPayloadSize, "V15", "BTOP has %llu bytes, the grid has %llu tiles of 8 bytes",
                (unsigned long long)top_section_.copy.size, (unsigned long long)tiles);
  const std::uint64_t brick_bytes = std::uint64_t(4) << (3 * view_.brick_log2_);
  if (pool_section_.copy.size % brick_bytes != 0 || pool_section_.copy.size / brick_bytes > fmt::kMaxPoolBricks)
    return fail(Status::kBadPayloadSize, "V15", "BPOL has %llu bytes, not a whole number of %llu-byte bricks",
                (unsigned long long)pool_section_.copy.size, (unsigned long long)brick_bytes);
  view_.top_ = reinterpret_cast<const std::uint64_t*>(at(top_section_.copy.offset));
  view_.pool_ = reinterpret_cast<const std::uint32_t*>(at(pool_section_.copy.offset));
  return checkTopEntries(pool_section_.copy.size / brick_bytes);
}

Status ViewBuilder::checkTopEntries(std::uint64_t pool_bricks) {
  const std::uint64_t tiles = top_section_.copy.size / 8;
  // A plane that matters crosses the band somewhere in its tile: |d_c| <= band + tile diagonal.
  const float max_plane_distance =
      grid_.band + 2.0f * fmt::kHalfCubeDiagonal * float(grid_.brick_size) * grid_.voxel_size;
  TileCounts counts;
  for (std::uint64_t t = 0; t < tiles; ++t) {
    const std::uint64_t entry = view_.top_[t];
    switch (fmt::entryKind(entry)) {
    case fmt::TileKind::kFarOutside:
    case fmt::TileKind::kFarInside:
      if ((entry >> 2) != 0)
        return fail(Status::kBadTileEntry, "V16", "far tile %llu has reserved bits set", (unsigned long long)t);
      ++(fmt::entryKind(entry) == fmt::TileKind::kFarOutside ? counts.far_outside : counts.far_inside);
      break;
    case fmt::TileKind::kPlane:
      if (!(std::fabs(fmt::entryPlaneDistance(entry)) <= max_plane_distance))
        return fail(Status::kBadTileEntry, "V16",
                    "plane tile %llu has distance %g at its centre, beyond band + diagonal", (unsigned long long)t,
                    double(fmt::entryPlaneDistance(entry)));
      ++counts.plane;
      break;
    case fmt::TileKind::kBrick:
      if (fmt::entryPoolIndex(entry) >= pool_bricks)
        return fail(Status::kBadTileEntry, "V16", "tile %llu refers to brick %u, the pool holds %llu",
                    (unsigned long long)t, fmt::entryPoolIndex(entry), (unsigned long long)pool_bricks);
      ++counts.brick;
      break;
    }
  }
  view_.tiles_ = counts;
  return Status::kOk;
}

// V19 (1.2): the optional LIFT section holds one int16 per voxel (dense) or per tile and pool word
// (bricked); every int16 is a valid lift.
Status ViewBuilder::checkLift() {
  if (!lift_section_.present) return Status::kOk;
  const std::uint64_t entries = grid_.encoding == fmt::Encoding::kDense
                                    ? dense_section_.copy.size / sizeof(fmt::DenseVoxel)
                                    : top_section_.copy.size / 8 + pool_section_.copy.size / 4;
  if (lift_section_.copy.size != entries * 2)
    return fail(Status::kBadPayloadSize, "V19", "LIFT has %llu bytes, the grid needs %llu lifts of 2 bytes",
                (unsigned long long)lift_section_.copy.size, (unsigned long long)entries);
  view_.lift_ = reinterpret_cast<const std::int16_t*>(at(lift_section_.copy.offset));
  if (grid_.encoding == fmt::Encoding::kBricked) view_.lift_pool_ = view_.lift_ + top_section_.copy.size / 8;
  view_.lift_step_ = fmt::liftStep(grid_.band);
  return Status::kOk;
}

// V20 (1.2) and V21 (1.3): the optional GRAD and SHAD sections hold one u16 per voxel (dense) or per
// pool word (bricked); every u16 is a valid octahedral normal. SHAD pads to an even count, so the SIMD
// kernels may read it 32 bits at a time (sample_lanes.h shadingLanes).
Status ViewBuilder::checkWordNormals(const Found& section, const char* rule, bool padded, const std::uint16_t** out) {
  if (!section.present) return Status::kOk;
  std::uint64_t entries = grid_.encoding == fmt::Encoding::kDense ? dense_section_.copy.size / sizeof(fmt::DenseVoxel)
                                                                  : pool_section_.copy.size / 4;
  if (padded) entries += entries % 2;
  if (section.copy.size != entries * 2)
    return fail(Status::kBadPayloadSize, rule, "%.4s has %llu bytes, the grid needs %llu normals of 2 bytes",
                reinterpret_cast<const char*>(&section.copy.tag), (unsigned long long)section.copy.size,
                (unsigned long long)entries);
  *out = reinterpret_cast<const std::uint16_t*>(at(section.copy.offset));
  return Status::kOk;
}

// V22 (1.3): the optional PLN2 section, bricked files only: its header, then whole arrays of masks,
// records, first indices and slots, with exactly the records the masks count. Each slot is
// kNoSecondPlanes or a block, only plane and brick tiles (the ones with band voxels) have blocks, and each
// mask word's first index is the count of the records before it, so every record index a lookup forms
// is in range. Every record is a valid bound or none (its reserved bits are ignored).
Status ViewBuilder::checkSecondPlanes() {
  if (!second_section_.present) return Status::kOk;
  if (grid_.encoding != fmt::Encoding::kBricked)
    return fail(Status::kBadPayloadSize, "V22", "PLN2 in a dense file: second planes are for bricked files only");
  const std::uint64_t tiles = top_section_.copy.size / 8, size = second_section_.copy.size;
  const std::uint64_t mask_words = fmt::secondPlaneMaskWords(view_.brick_log2_);
  fmt::SecondPlanesHeader header{};
  if (size >= sizeof header) std::memcpy(&header, at(second_section_.copy.offset), sizeof header);
  const std::uint64_t masks_total = std::uint64_t(header.blocks) * mask_words;
  const std::uint64_t expected = sizeof header + masks_total * 12 + std::uint64_t(header.planes) * 8 + tiles * 4;
  if (size < sizeof header || size != expected)
    return fail(Status::kBadPayloadSize, "V22",
                "PLN2 has %llu bytes; %u blocks of second planes, %u planes and %llu tiles need %llu",
                (unsigned long long)size, header.blocks, header.planes, (unsigned long long)tiles,
                (unsigned long long)expected);
  const std::uint8_t* base = at(second_section_.copy.offset) + sizeof header;
  const auto* masks = reinterpret_cast<const std::uint64_t*>(base);
  const auto* records = masks + masks_total;
  const auto* first = reinterpret_cast<const std::uint32_t*>(records + header.planes);
  const auto* slots = first + masks_total;
  std::uint64_t running = 0;
  for (std::uint64_t m = 0; m < masks_total; ++m) {
    if (first[m] != running)
      return fail(Status::kBadPayloadSize, "V22",
                  "PLN2 mask word %llu starts at record %u, %llu records come before it", (unsigned long long)m,
                  first[m], (unsigned long long)running);
    running += fmt::bitCount(masks[m]);
  }
  if (running != header.planes)
    return fail(Status::kBadPayloadSize, "V22", "PLN2 masks count %llu records, the header %u",
                (unsigned long long)running, header.planes);
  for (std::uint64_t t = 0; t < tiles; ++t) {
    if (slots[t] == fmt::kNoSecondPlanes) continue;
    if (slots[t] >= header.blocks)
      return fail(Status::kBadTileEntry, "V22", "tile %llu refers to second-plane block %u, PLN2 holds %u",
                  (unsigned long long)t, slots[t], header.blocks);
    const fmt::TileKind kind = fmt::entryKind(view_.top_[t]);
    if (kind != fmt::TileKind::kPlane && kind != fmt::TileKind::kBrick)
      return fail(Status::kBadTileEntry, "V22", "far tile %llu has a block of second planes", (unsigned long long)t);
  }
  view_.second_masks_ = masks;
  view_.second_records_ = records;
  view_.second_first_ = first;
  view_.second_slots_ = slots;
  view_.second_mask_words_ = std::uint32_t(mask_words);
  view_.second_count_ = header.planes;
  view_.second_step_ = fmt::secondPlaneStep(grid_.band);
  view_.second_raise_step_ = fmt::secondPlaneRaiseStep(grid_.band);
  return Status::kOk;
}

Status View::open(const void* data, std::size_t size, View* out_view, Diagnostic* out_diag) {
  if (out_view == nullptr) return writeDiagnostic(out_diag, Status::kInvalidArgument, "out_view is null");
  *out_view = View();
  if (out_diag != nullptr) *out_diag = Diagnostic();
  ViewBuilder builder(static_cast<const std::uint8_t*>(data), size, out_diag);
  return builder.run(out_view);
}

} // namespace dng
