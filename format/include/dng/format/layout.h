// On-disk layout of a .dng file, format version 1.
//
// docs/FORMAT.md is the binding specification; this header mirrors it. Every struct here is plain old
// data stored little-endian at the byte offsets given in the comments, and every size and offset is
// pinned with static_assert below so an accidental change breaks the build instead of the files.
//
// Byte order: little-endian only. Readers on big-endian hosts refuse to open files (see
// isLittleEndianHost()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace dng {
namespace format {

/// First eight bytes of every file. The high-bit first byte and the CR LF / Ctrl-Z / LF tail catch
/// 7-bit transfers and text-mode newline conversion, as in PNG.
inline constexpr unsigned char kMagic[8] = {0x89, 'D', 'N', 'G', '\r', '\n', 0x1A, '\n'};

/// A major bump breaks compatibility; a minor bump only adds (new optional sections, new fields in
/// reserved bytes that older readers may ignore).
inline constexpr std::uint16_t kVersionMajor = 1;
/// 1.1: GridSection::flags; 1.2: LIFT and GRAD; 1.3: SHAD and PLN2.
inline constexpr std::uint16_t kVersionMinor = 3;

inline constexpr std::uint32_t kHeaderSize = 128;
inline constexpr std::uint32_t kSectionAlignment = 64;
inline constexpr std::uint32_t kMaxSections = 256;

/// Section flag bit 0: a reader that does not know the tag must refuse the file.
inline constexpr std::uint32_t kSectionRequired = 1u;

/// Builds a FourCC tag whose bytes on disk read as the four characters in order.
constexpr std::uint32_t makeTag(char a, char b, char c, char d) {
  return std::uint32_t(std::uint8_t(a)) | std::uint32_t(std::uint8_t(b)) << 8 | std::uint32_t(std::uint8_t(c)) << 16 |
         std::uint32_t(std::uint8_t(d)) << 24;
}

inline constexpr std::uint32_t kTagGrid = makeTag('G', 'R', 'I', 'D');      ///< GridSection
inline constexpr std::uint32_t kTagMetadata = makeTag('M', 'E', 'T', 'A');  ///< UTF-8 JSON
inline constexpr std::uint32_t kTagDense = makeTag('D', 'E', 'N', 'S');     ///< DenseVoxel[]
inline constexpr std::uint32_t kTagBrickTop = makeTag('B', 'T', 'O', 'P');  ///< u64 top entries
inline constexpr std::uint32_t kTagBrickPool = makeTag('B', 'P', 'O', 'L'); ///< u32 voxel words
/// Optional, since 1.2: int16 lifts that give back the distances as they were before the planes were
/// lowered (docs/FORMAT.md §5.2). Bricked: one per BTOP entry, then one per BPOL word, in their orders.
/// Dense: one per voxel, x fastest. A lift's value is code * liftStep(band) (codec.h).
inline constexpr std::uint32_t kTagLift = makeTag('L', 'I', 'F', 'T');
/// Optional, since 1.2: the distance's own gradient where the stored normals are something else (the
/// blurred modes), for the accurate query (docs/FORMAT.md §5.3). One u16 octahedral normal
/// (gradientWord, codec.h) per BPOL word (bricked) or per voxel (dense), in their orders.
inline constexpr std::uint32_t kTagGradient = makeTag('G', 'R', 'A', 'D');
/// Optional, since 1.3: the normals of the field's mode (blurred, potential gradient) where the stored
/// planes carry the distance's own gradient, for the responses and the queries' normals
/// (docs/FORMAT.md §5.4). One u16 octahedral normal (gradientWord, codec.h) per BPOL word (bricked) or
/// per voxel (dense), in their orders, then one u16 of zero padding when the count is odd, so that
/// readers may load the section 32 bits at a time. A reader that ignores it reads the planes' normals.
inline constexpr std::uint32_t kTagShading = makeTag('S', 'H', 'A', 'D');
/// Optional, since 1.3, bricked files only: a second bound for the few voxels beside edges and creases
/// where one plane cannot bound the distance well over the whole cell (docs/FORMAT.md §5.5), stored
/// sparsely: SecondPlanesHeader, then per block (a tile that has any) a bit mask of its voxels (B^3 / 64
/// u64 each), then the bounds (u64 each: secondPlaneRecord, codec.h), block by block in voxel order,
/// then per mask word the index of its first bound (u32), then one u32 slot per BTOP entry
/// (kNoSecondPlanes, or the tile's block). Only the step's walk reads them; a reader that ignores the
/// section proves less beside edges, never wrongly.
inline constexpr std::uint32_t kTagSecondPlanes = makeTag('P', 'L', 'N', '2');

/// File header: 128 bytes at offset 0.
struct FileHeader {
  unsigned char magic[8];             // 0   kMagic
  std::uint16_t version_major;        // 8   kVersionMajor
  std::uint16_t version_minor;        // 10  kVersionMinor
  std::uint32_t header_size;          // 12  kHeaderSize
  std::uint64_t file_size;            // 16  total bytes, must equal the real length
  std::uint32_t flags;                // 24  reserved, written 0, ignored by 1.x readers
  std::uint32_t section_count;        // 28  entries in the section table, <= kMaxSections
  std::uint64_t section_table_offset; // 32  64-aligned, >= kHeaderSize
  std::uint64_t section_table_hash;   // 40  XXH64 (seed 0) of the section table bytes
  unsigned char reserved[72];         // 48  written 0, ignored by 1.x readers
  std::uint64_t header_hash;          // 120 XXH64 (seed 0) of header bytes [0, 120)
};

/// One entry of the section table: 32 bytes.
struct SectionEntry {
  std::uint32_t tag;    // 0   FourCC, see kTag*
  std::uint32_t flags;  // 4   bit 0 = kSectionRequired; other bits reserved
  std::uint64_t offset; // 8   from the file start, 64-aligned
  std::uint64_t size;   // 16  bytes of payload (padding after it is not counted)
  std::uint64_t hash;   // 24  XXH64 (seed 0) of the payload bytes
};

/// Payload encodings named in GridSection::encoding.
enum class Encoding : std::uint32_t {
  kDense = 0,   ///< DENS section: one DenseVoxel per voxel, x fastest
  kBricked = 1, ///< BTOP + BPOL sections: the paper's two-level "compressed plane grid" (§3.2)
};

/// GRID section: 64 bytes (a later minor version may append fields; readers accept size >= 64).
/// The grid covers the box [origin, origin + dims * voxel_size) of the body's local frame; voxel
/// (i, j, k) has its centre at origin + (i + 0.5, j + 0.5, k + 0.5) * voxel_size.
struct GridSection {
  float origin[3];             // 0   local-frame position of the grid's minimum corner
  float voxel_size;            // 12  edge length of a cubic voxel, > 0
  std::uint32_t dims[3];       // 16  voxels along x, y, z, each >= 1
  float band;                  // 28  |distance| >= band counts as "far", > 0, local units
  std::uint32_t encoding;      // 32  Encoding
  std::uint32_t brick_log2;    // 36  bricked: 2, 3 or 4 (brick edge 4, 8, 16); dense: 0
  std::uint32_t brick_dims[3]; // 40  bricked: ceil(dims / brick edge); dense: 0
  float tolerance_distance;    // 52  bricked: plane/far tile tolerance, in voxels
  float tolerance_normal_deg;  // 56  bricked: plane tile normal tolerance, in degrees
  std::uint32_t flags;         // 60  kGridFlag* bits (1.1; written 0 by 1.0 writers), others reserved
};

/// GridSection::flags bit 0 (since 1.1): wherever an in-band voxel's plane, d + n . (p - c), capped at
/// the guaranteed reach, reads >= 0 in the voxel's cell, it is at most the true signed distance there
/// plus a small epsilon, as dngbake makes them (docs/FORMAT.md §5.1 states it exactly).
/// Readers that do not know a bit ignore it.
inline constexpr std::uint32_t kGridFlagConservativePlanes = 1u;

/// One voxel of the dense encoding: 16 bytes.
struct DenseVoxel {
  float distance;  // 0   signed distance at the voxel centre, negative inside
  float normal[3]; // 4   unit normal (V14: finite, of length at most 1 + 1e-4; used as stored)
};

/// The start of a PLN2 section: 8 bytes.
struct SecondPlanesHeader {
  std::uint32_t blocks; // 0  tiles with second bounds
  std::uint32_t planes; // 4  voxels with a second bound, in all
};

/// Kind of a brick-top entry, stored in its low two bits.
enum class TileKind : std::uint32_t {
  kFarOutside = 0, ///< every voxel at distance >= band: no payload
  kFarInside = 1,  ///< every voxel at distance <= -band: no payload
  kPlane = 2,      ///< one plane for the whole tile: d = d_c + n . (p - c)
  kBrick = 3,      ///< one brick of quantized voxel words in the pool
};

/// How many tiles of each kind a bricked grid has: what the encoder wrote (EncodeStats::tiles) and
/// what the reader counted at open (View::tileCounts), one type so the two compare directly. Not on disk.
struct TileCounts {
  std::uint64_t far_outside = 0;
  std::uint64_t far_inside = 0;
  std::uint64_t plane = 0;
  std::uint64_t brick = 0;
  std::uint64_t total() const { return far_outside + far_inside + plane + brick; }
};

static_assert(sizeof(FileHeader) == 128, "FileHeader is 128 bytes on disk");
static_assert(offsetof(FileHeader, version_major) == 8);
static_assert(offsetof(FileHeader, version_minor) == 10);
static_assert(offsetof(FileHeader, header_size) == 12);
static_assert(offsetof(FileHeader, file_size) == 16);
static_assert(offsetof(FileHeader, flags) == 24);
static_assert(offsetof(FileHeader, section_count) == 28);
static_assert(offsetof(FileHeader, section_table_offset) == 32);
static_assert(offsetof(FileHeader, section_table_hash) == 40);
static_assert(offsetof(FileHeader, reserved) == 48);
static_assert(offsetof(FileHeader, header_hash) == 120);

static_assert(sizeof(SectionEntry) == 32, "SectionEntry is 32 bytes on disk");
static_assert(offsetof(SectionEntry, flags) == 4);
static_assert(offsetof(SectionEntry, offset) == 8);
static_assert(offsetof(SectionEntry, size) == 16);
static_assert(offsetof(SectionEntry, hash) == 24);

static_assert(sizeof(GridSection) == 64, "GridSection is 64 bytes on disk");
static_assert(offsetof(GridSection, voxel_size) == 12);
static_assert(offsetof(GridSection, dims) == 16);
static_assert(offsetof(GridSection, band) == 28);
static_assert(offsetof(GridSection, encoding) == 32);
static_assert(offsetof(GridSection, brick_log2) == 36);
static_assert(offsetof(GridSection, brick_dims) == 40);
static_assert(offsetof(GridSection, tolerance_distance) == 52);
static_assert(offsetof(GridSection, tolerance_normal_deg) == 56);
static_assert(offsetof(GridSection, flags) == 60);

static_assert(sizeof(SecondPlanesHeader) == 8, "SecondPlanesHeader is 8 bytes on disk");
static_assert(offsetof(SecondPlanesHeader, planes) == 4);

static_assert(sizeof(DenseVoxel) == 16, "DenseVoxel is 16 bytes on disk");
static_assert(offsetof(DenseVoxel, normal) == 4);

/// True when the host stores integers little-endian, the only order this format is read in.
inline bool isLittleEndianHost() {
  const std::uint16_t probe = 1;
  unsigned char first = 0;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

} // namespace format
} // namespace dng
