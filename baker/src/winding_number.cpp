// Fast generalized winding number: the sign of the DN field (docs/DESIGN.md §5.6).
//
// w(q) = sum over triangles of the solid angle they subtend at q, / 4 pi (Jacobson, Kavan &
// Sorkine-Hornung, "Robust Inside-Outside Segmentation using Generalized Winding Numbers", 2013).
// Far clusters of triangles are replaced by one dipole (Barill, Dickson, Schmidt, Levin & Jacobson,
// "Fast Winding Numbers for Soups and Clouds", 2018): with N = sum of area-weighted normals and p the
// area-weighted centroid, w_cluster(q) ~ (p - q) . N / (4 pi |p - q|^3), used when |p - q| > 2 r.
// Near clusters open up down to exact solid angles (van Oosterom & Strackee 1983). The hierarchy is
// built by Embree's generic BVH builder; the dipoles are summed here bottom-up.
#include "stages.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>

namespace dng {
namespace baker {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kOpenRatio = 2.0; // Barill et al.'s beta: open a cluster closer than 2 radii

struct D3 {
  double x = 0, y = 0, z = 0;
};
D3 toD3(Vec3f v) { return {v.x, v.y, v.z}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator*(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dotD(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 crossD(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double lengthD(D3 a) { return std::sqrt(dotD(a, a)); }

// One node of the hierarchy: two children, or a leaf with a few triangles. Memory from Embree's
// allocator, owned by the RTCBVH.
struct Node {
  Node* child[2] = {nullptr, nullptr};
  const std::uint32_t* triangles = nullptr; // leaf only
  std::uint32_t triangle_count = 0;
  D3 centroid;   // area-weighted
  D3 normal_sum; // sum of area-weighted normals (half cross products)
  double area = 0;
  double radius = 0; // bounds every triangle vertex around the centroid
};

void* createNode(RTCThreadLocalAllocator alloc, unsigned int, void*) {
  return new (rtcThreadLocalAlloc(alloc, sizeof(Node), 16)) Node;
}
void setChildren(void* node, void** children, unsigned int count, void*) {
  for (unsigned int i = 0; i < count && i < 2; ++i)
    static_cast<Node*>(node)->child[i] = static_cast<Node*>(children[i]);
}
void setBounds(void*, const RTCBounds**, unsigned int, void*) {}
void* createLeaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count, void*) {
  auto* leaf = new (rtcThreadLocalAlloc(alloc, sizeof(Node), 16)) Node;
  auto* ids = static_cast<std::uint32_t*>(rtcThreadLocalAlloc(alloc, count * sizeof(std::uint32_t), 4));
  for (size_t i = 0; i < count; ++i)
    ids[i] = prims[i].primID;
  leaf->triangles = ids;
  leaf->triangle_count = std::uint32_t(count);
  return leaf;
}

// Exact solid angle of triangle abc seen from q, divided by 4 pi.
double triangleWinding(D3 a, D3 b, D3 c) {
  const double la = lengthD(a), lb = lengthD(b), lc = lengthD(c);
  const double numerator = dotD(a, crossD(b, c));
  const double denominator = la * lb * lc + dotD(a, b) * lc + dotD(a, c) * lb + dotD(b, c) * la;
  return std::atan2(numerator, denominator) / (2.0 * kPi);
}

} // namespace

struct WindingNumber::Impl {
  RTCDevice device = nullptr;
  RTCBVH bvh = nullptr;
  Node* root = nullptr;
  const TriangleSoup* soup = nullptr;
  ~Impl() {
    if (bvh) rtcReleaseBVH(bvh);
    if (device) rtcReleaseDevice(device);
  }

  // Post-order: dipole sums of a subtree, and a radius around its centroid.
  void summarize(Node* node) {
    if (node->triangles == nullptr) {
      for (Node* c : node->child) {
        if (c) summarize(c);
      }
      D3 weighted;
      for (Node* c : node->child) {
        if (!c) continue;
        node->area += c->area;
        node->normal_sum = node->normal_sum + c->normal_sum;
        weighted = weighted + c->centroid * c->area;
      }
      node->centroid =
          node->area > 0 ? weighted * (1.0 / node->area) : (node->child[0] ? node->child[0]->centroid : D3{});
      for (Node* c : node->child) {
        if (c) node->radius = std::max(node->radius, lengthD(c->centroid - node->centroid) + c->radius);
      }
      return;
    }
    D3 weighted;
    for (std::uint32_t i = 0; i < node->triangle_count; ++i) {
      const auto& t = soup->triangles[node->triangles[i]];
      const D3 a = toD3(soup->vertices[t[0]]), b = toD3(soup->vertices[t[1]]), c = toD3(soup->vertices[t[2]]);
      const D3 n = crossD(b - a, c - a) * 0.5;
      const double area = lengthD(n);
      node->normal_sum = node->normal_sum + n;
      node->area += area;
      weighted = weighted + (a + b + c) * (area / 3.0);
    }
    const auto& first = soup->triangles[node->triangles[0]];
    node->centroid = node->area > 0 ? weighted * (1.0 / node->area) : toD3(soup->vertices[first[0]]);
    for (std::uint32_t i = 0; i < node->triangle_count; ++i) {
      for (std::uint32_t v : soup->triangles[node->triangles[i]])
        node->radius = std::max(node->radius, lengthD(toD3(soup->vertices[v]) - node->centroid));
    }
  }

  double evaluate(const Node* node, D3 q) const {
    const D3 to_centroid = node->centroid - q;
    const double distance = lengthD(to_centroid);
    if (distance > kOpenRatio * node->radius)
      return dotD(to_centroid, node->normal_sum) / (4.0 * kPi * distance * distance * distance);
    if (node->triangles == nullptr) {
      double sum = 0.0;
      for (const Node* c : node->child) {
        if (c) sum += evaluate(c, q);
      }
      return sum;
    }
    double sum = 0.0;
    for (std::uint32_t i = 0; i < node->triangle_count; ++i) {
      const auto& t = soup->triangles[node->triangles[i]];
      sum += triangleWinding(toD3(soup->vertices[t[0]]) - q, toD3(soup->vertices[t[1]]) - q,
                             toD3(soup->vertices[t[2]]) - q);
    }
    return sum;
  }
};

WindingNumber::WindingNumber() : impl_(std::make_unique<Impl>()) {}
WindingNumber::~WindingNumber() = default;

BakeStatus WindingNumber::build(const TriangleSoup& soup) {
  impl_ = std::make_unique<Impl>();
  impl_->soup = &soup;
  if (soup.triangles.empty()) return BakeStatus::success();
  impl_->device = rtcNewDevice(nullptr);
  if (impl_->device == nullptr) return BakeStatus::failure(BakeError::kInternal, "Embree could not create a device");
  std::vector<RTCBuildPrimitive> prims;
  prims.reserve(soup.triangles.size());
  for (std::uint32_t t = 0; t < soup.triangles.size(); ++t) {
    RTCBuildPrimitive p;
    const Vec3f a = soup.vertices[soup.triangles[t][0]], b = soup.vertices[soup.triangles[t][1]],
                c = soup.vertices[soup.triangles[t][2]];
    p.lower_x = std::min({a.x, b.x, c.x}), p.lower_y = std::min({a.y, b.y, c.y}), p.lower_z = std::min({a.z, b.z, c.z});
    p.upper_x = std::max({a.x, b.x, c.x}), p.upper_y = std::max({a.y, b.y, c.y}), p.upper_z = std::max({a.z, b.z, c.z});
    p.geomID = 0;
    p.primID = t;
    prims.push_back(p);
  }
  impl_->bvh = rtcNewBVH(impl_->device);
  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.byteSize = sizeof(args);
  args.buildQuality = RTC_BUILD_QUALITY_MEDIUM;
  args.maxBranchingFactor = 2;
  args.maxDepth = 1024;
  args.maxLeafSize = 8;
  args.bvh = impl_->bvh;
  args.primitives = prims.data();
  args.primitiveCount = prims.size();
  args.primitiveArrayCapacity = prims.size();
  args.createNode = createNode;
  args.setNodeChildren = setChildren;
  args.setNodeBounds = setBounds;
  args.createLeaf = createLeaf;
  impl_->root = static_cast<Node*>(rtcBuildBVH(&args));
  if (impl_->root == nullptr) return BakeStatus::failure(BakeError::kInternal, "Embree could not build the hierarchy");
  impl_->summarize(impl_->root);
  return BakeStatus::success();
}

double WindingNumber::evaluate(Vec3f q) const {
  return impl_->root == nullptr ? 0.0 : impl_->evaluate(impl_->root, toD3(q));
}

} // namespace baker
} // namespace dng
