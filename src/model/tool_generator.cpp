// Built-in instruments as surfaces of revolution (see tool_generator.h for the frames).
#include "model/tool_generator.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

namespace dentsim {
namespace {

constexpr double kShankRadius = 0.8;     // FG shank, 1.6 mm diameter [mm]
constexpr double kBurLength = 19.0;      // overall length of an FG bur [mm]
constexpr int kBurSegments = 48;         // facets around a bur
constexpr int kArcSteps = 12;            // profile steps per quarter circle

// cos and sin from their Taylor series with only + - * /, so that the meshes do not depend on the
// C library's rounding. |angle| <= pi keeps 30 terms far past double precision.
struct CosSin {
  double c, s;
};
CosSin cosSin(double angle) {
  while (angle > std::numbers::pi) angle -= 2.0 * std::numbers::pi;
  while (angle < -std::numbers::pi) angle += 2.0 * std::numbers::pi;
  double c = 0.0, s = 0.0, term = 1.0;  // term = angle^n / n!
  for (int n = 0; n < 30; ++n) {
    if (n % 4 == 0) c += term;
    else if (n % 4 == 1) s += term;
    else if (n % 4 == 2) c -= term;
    else s -= term;
    term *= angle / double(n + 1);
  }
  return {c, s};
}

// atan(t) from its series with only + - * /, for the same reason; |t| <= 0.25 (a taper under 14
// degrees) keeps 30 terms far past double precision.
double atanSmall(double t) {
  assert(std::abs(t) <= 0.25);
  double sum = 0.0, power = t;  // power = t^(2n+1)
  for (int n = 0; n < 30; ++n) {
    sum += (n % 2 == 0 ? power : -power) / double(2 * n + 1);
    power *= t * t;
  }
  return sum;
}

struct ProfilePoint {
  double r, s;  // radius from the axis and position along it [mm]
};

// An axis of revolution: origin, direction w, and u, v with u x v = w.
struct Axis {
  Vec3d o, u, v, w;
};
Axis zAxis() { return {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}; }
// Axis through o in the xz-plane, `deg` degrees from +x toward +z (negative: toward -z), with
// `sign` = -1 pointing it toward -x.
Axis tiltedAxis(const Vec3d& o, double deg, double sign) {
  const CosSin cs = cosSin(deg * std::numbers::pi / 180.0);
  const Vec3d w{sign * cs.c, 0.0, cs.s};
  // u = y x w is perpendicular to w in the xz-plane; v = w x u completes the frame.
  const Vec3d u{w[2], 0.0, -w[0]};
  const Vec3d v{w[1] * u[2] - w[2] * u[1], w[2] * u[0] - w[0] * u[2], w[0] * u[1] - w[1] * u[0]};
  return {o, u, v, w};
}

// Revolves a profile that runs from a pole (r = 0) to a pole, every point between having r > 0,
// into a closed shell appended to `mesh`. Rings turn counter-clockwise about w, so with the
// profile climbing along w every face points away from the axis.
void revolve(TriangleMesh& mesh, const std::vector<ProfilePoint>& profile, const Axis& ax, int segments) {
  assert(profile.size() >= 3 && profile.front().r == 0.0 && profile.back().r == 0.0);
  auto place = [&](double r, double s, double c, double sn) {
    Vec3f p{};
    for (int a = 0; a < 3; ++a) p[a] = float(ax.o[a] + r * (c * ax.u[a] + sn * ax.v[a]) + s * ax.w[a]);
    mesh.positions.push_back(p);
  };
  std::vector<CosSin> ring(static_cast<size_t>(segments));
  for (int j = 0; j < segments; ++j) ring[size_t(j)] = cosSin(2.0 * std::numbers::pi * j / segments);

  const uint32_t first = uint32_t(mesh.positions.size());
  place(0.0, profile.front().s, 1.0, 0.0);
  const size_t rings = profile.size() - 2;
  for (size_t i = 1; i + 1 < profile.size(); ++i) {
    assert(profile[i].r > 0.0);
    for (const CosSin& cs : ring) place(profile[i].r, profile[i].s, cs.c, cs.s);
  }
  const uint32_t last = uint32_t(mesh.positions.size());
  place(0.0, profile.back().s, 1.0, 0.0);

  const uint32_t n = uint32_t(segments);
  auto at = [&](size_t i, uint32_t j) { return first + 1 + uint32_t(i) * n + (j % n); };
  for (uint32_t j = 0; j < n; ++j) mesh.triangles.push_back({first, at(0, j + 1), at(0, j)});
  for (size_t i = 0; i + 1 < rings; ++i)
    for (uint32_t j = 0; j < n; ++j) {
      mesh.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  for (uint32_t j = 0; j < n; ++j) mesh.triangles.push_back({at(rings - 1, j), at(rings - 1, j + 1), last});
}

// Arc of the circle about (0, centre) of radius r, from polar angle a0 to a1 (0 = the bottom pole,
// pi = the top), end points included.
void appendArc(std::vector<ProfilePoint>& out, double centre, double r, double a0, double a1) {
  const int steps = std::max(1, int(std::ceil((a1 - a0) / (0.5 * std::numbers::pi) * kArcSteps)));
  for (int i = 0; i <= steps; ++i) {
    const CosSin cs = cosSin(a0 + (a1 - a0) * i / steps);
    out.push_back({r * cs.s, centre - r * cs.c});
  }
}

// The shared upper part of a bur: neck at radius `neck` from `neck_start`, a cone to the shank,
// the shank to the chamfered end.
void appendNeckAndShank(std::vector<ProfilePoint>& p, double neck, double neck_start, double neck_end) {
  p.push_back({neck, neck_start});
  p.push_back({neck, neck_end});
  p.push_back({kShankRadius, neck_end + 1.5});
  p.push_back({kShankRadius, kBurLength - 0.25});
  p.push_back({kShankRadius - 0.25, kBurLength});
  p.push_back({0.0, kBurLength});
}

TriangleMesh roundBur(double d) {
  const double r = 0.5 * d, neck = 0.55 * r;
  // The sphere up to its equator (so the widest ring is exactly the nominal diameter), then on
  // to the latitude where its radius meets the neck.
  std::vector<ProfilePoint> p;
  appendArc(p, r, r, 0.0, 0.5 * std::numbers::pi);
  const double top = r + r * std::sqrt(1.0 - 0.55 * 0.55);
  for (int i = 1; i < kArcSteps; ++i) {
    const double s = r + (top - r) * i / kArcSteps;
    p.push_back({std::sqrt(r * r - (s - r) * (s - r)), s});
  }
  appendNeckAndShank(p, neck, top, 3.0 + d);
  TriangleMesh m;
  revolve(m, p, zAxis(), kBurSegments);
  return m;
}

TriangleMesh fissureBur(double d, double head_length) {
  const double r = 0.5 * d, neck = 0.55 * r;
  std::vector<ProfilePoint> p;
  appendArc(p, r, r, 0.0, 0.5 * std::numbers::pi);  // rounded end
  p.push_back({r, head_length});
  appendNeckAndShank(p, neck, head_length + 0.2, head_length + 1.5);
  TriangleMesh m;
  revolve(m, p, zAxis(), kBurSegments);
  return m;
}

// A tapered head (chamfer or shoulder bur): a cone from its tip radius at z = 0 to its top radius
// at the cutting length, closed below by an arc tangent to the cone: for a chamfer bur a sphere
// resting on the tip, for a shoulder bur a small fillet between the flat end and the cone.
constexpr double kShoulderEdgeMm = 0.05;  // fillet of a shoulder bur's end edge: a sharp but not knife-like margin [mm]
constexpr int kShoulderEdgeSteps = 4;     // profile steps around that fillet: it is a twentieth of a millimetre

struct TaperedHead {
  double tip_r, top_r, length;  // the cone's radius at z = 0 and at z = length [mm]
  double tan_a, sin_a, cos_a;   // of the half-angle
  double angle;                 // the half-angle [rad]
  bool round_end;               // chamfer bur: the sphere; shoulder bur: flat with a fillet
  double arc_r;                 // radius of the end's arc [mm]
  double arc_centre_r;          // its centre: (arc_centre_r, arc_r) in (radius, height) [mm]
  double cone_from;             // height where the arc meets the cone [mm]

  explicit TaperedHead(const ToolSpec& spec)
      : tip_r(0.5 * spec.tip_diameter_mm), top_r(0.5 * spec.head_diameter_mm), length(spec.cutting_length_mm),
        round_end(spec.kind == ToolKind::ChamferBur) {
    tan_a = (top_r - tip_r) / length;
    cos_a = 1.0 / std::sqrt(1.0 + tan_a * tan_a);
    sin_a = tan_a * cos_a;
    angle = atanSmall(tan_a);
    // The arc's centre lies at its radius above the tip plane and at its radius from the cone
    // r = tip_r + z tan_a; the sphere's centre is on the axis, the fillet's at the end's rim.
    if (round_end) {
      arc_r = tip_r * cos_a / (1.0 - sin_a);
      arc_centre_r = 0.0;
    } else {
      arc_r = kShoulderEdgeMm;
      arc_centre_r = tip_r + arc_r * tan_a - arc_r / cos_a;
    }
    cone_from = arc_r * (1.0 - sin_a);
  }
  double radiusAt(double h) const {
    if (h >= cone_from) return tip_r + h * tan_a;
    const double dz = arc_r - h;
    return arc_centre_r + std::sqrt(std::max(0.0, arc_r * arc_r - dz * dz));
  }
};

TriangleMesh taperedBur(const ToolSpec& spec) {
  const TaperedHead head(spec);
  std::vector<ProfilePoint> p;
  if (!head.round_end) p.push_back({0.0, 0.0});  // the flat end's centre
  // The arc from the tip plane (polar angle 0) to where it turns into the cone (90 degrees less the taper).
  const double sweep = 0.5 * std::numbers::pi - head.angle;
  const int steps = head.round_end ? int(std::ceil(sweep / (0.5 * std::numbers::pi) * kArcSteps)) : kShoulderEdgeSteps;
  for (int i = 0; i <= steps; ++i) {
    const CosSin cs = cosSin(sweep * i / steps);
    p.push_back({head.arc_centre_r + head.arc_r * cs.s, head.arc_r - head.arc_r * cs.c});
  }
  // The cone is straight: one ring at its top is all it needs (the assets' 10 MB budget counts).
  p.push_back({head.top_r, head.length});
  appendNeckAndShank(p, 0.55 * head.top_r, head.length + 0.2, head.length + 1.5);
  TriangleMesh m;
  revolve(m, p, zAxis(), kBurSegments);
  return m;
}

TriangleMesh handpiece() {
  TriangleMesh m;
  // Head: chuck nose (4 mm across) under a 10.5 mm cylinder with rounded rims.
  const std::vector<ProfilePoint> head{{0.0, 8.6},   {1.6, 8.6},   {2.0, 9.0},   {2.0, 9.5},
                                       {4.75, 9.5},  {5.1, 9.65},  {5.25, 10.0}, {5.25, 21.0},
                                       {5.1, 21.35}, {4.75, 21.5}, {0.0, 21.5}};
  revolve(m, head, zAxis(), 64);
  // Neck and body from inside the head (axis through its centre): a 7 mm neck widening into the
  // 12 mm grip body, rounded at the hose end about 104 mm from the head's axis.
  const std::vector<ProfilePoint> body{{0.0, 2.0},   {3.5, 2.0},   {3.5, 16.0},  {5.0, 26.0},
                                       {5.6, 32.0},  {6.0, 40.0},  {6.0, 100.0}, {5.5, 102.5},
                                       {4.0, 103.6}, {0.0, 104.0}};
  revolve(m, body, tiltedAxis({0.0, 0.0, 15.5}, 18.0, 1.0), 64);
  return m;
}

TriangleMesh mirror() {
  TriangleMesh m;
  // Disc of 22 mm (size 4), 2 mm thick, the reflective face at z = 0.
  const std::vector<ProfilePoint> disc{{0.0, -2.0},  {10.5, -2.0}, {10.9, -1.8}, {11.0, -1.4},
                                       {11.0, -0.3}, {kMirrorGlassRadiusMm, 0.0}, {0.0, 0.0}};
  revolve(m, disc, zAxis(), 96);
  // Neck from inside the disc's rim, thickening into the 8 mm handle, about 120 mm long.
  const std::vector<ProfilePoint> handle{{0.0, 0.0},   {0.85, 0.0},  {0.85, 4.0},   {1.25, 10.0},
                                         {1.25, 18.0}, {2.0, 22.0},  {4.0, 28.0},   {4.0, 146.0},
                                         {3.6, 147.6}, {2.5, 148.5}, {0.0, 149.0}};
  revolve(m, handle, tiltedAxis({-9.5, 0.0, -1.0}, -20.0, -1.0), 48);
  return m;
}

// tan(2 degrees): the half-angle makers give for 856 and 847 diamonds (assets/tools/README.md).
constexpr double kTan2Deg = 0.03492076949174773;
// The diameter at the tip of a head that narrows from `top` over `length` at 2 degrees a side.
constexpr double taperedTip(double top, double length) { return top - 2.0 * length * kTan2Deg; }

constexpr ToolSpec kCatalog[] = {
    {"round_bur_008", ToolKind::RoundBur, 0.8, 0.8, 0.8},
    {"round_bur_010", ToolKind::RoundBur, 1.0, 1.0, 1.0},
    {"round_bur_014", ToolKind::RoundBur, 1.4, 1.4, 1.4},
    {"round_bur_018", ToolKind::RoundBur, 1.8, 1.8, 1.8},
    {"fissure_bur_008", ToolKind::FissureBur, 0.8, 4.0, 0.8},
    {"fissure_bur_010", ToolKind::FissureBur, 1.0, 4.0, 1.0},
    {"fissure_bur_012", ToolKind::FissureBur, 1.2, 4.0, 1.2},
    {"chamfer_bur_016", ToolKind::ChamferBur, 1.6, 8.0, taperedTip(1.6, 8.0)},
    {"chamfer_bur_018", ToolKind::ChamferBur, 1.8, 8.0, taperedTip(1.8, 8.0)},
    {"shoulder_bur_014", ToolKind::ShoulderBur, 1.4, 8.0, taperedTip(1.4, 8.0)},
    {"shoulder_bur_016", ToolKind::ShoulderBur, 1.6, 8.0, taperedTip(1.6, 8.0)},
    {"turbine_handpiece", ToolKind::Handpiece, 10.5, 0.0, 0.0},
    {"mirror_size4", ToolKind::Mirror, 22.0, 0.0, 0.0},
};

}  // namespace

std::span<const ToolSpec> toolCatalog() { return kCatalog; }

const ToolSpec* findTool(std::string_view name) {
  for (const ToolSpec& t : kCatalog)
    if (name == t.name) return &t;
  return nullptr;
}

const char* toolKindName(ToolKind kind) {
  switch (kind) {
    case ToolKind::RoundBur: return "round_bur";
    case ToolKind::FissureBur: return "fissure_bur";
    case ToolKind::ChamferBur: return "chamfer_bur";
    case ToolKind::ShoulderBur: return "shoulder_bur";
    case ToolKind::Handpiece: return "handpiece";
    case ToolKind::Mirror: return "mirror";
  }
  return "unknown";
}

TriangleMesh generateTool(const ToolSpec& spec) {
  switch (spec.kind) {
    case ToolKind::RoundBur: return roundBur(spec.head_diameter_mm);
    case ToolKind::FissureBur: return fissureBur(spec.head_diameter_mm, spec.cutting_length_mm);
    case ToolKind::ChamferBur:
    case ToolKind::ShoulderBur: return taperedBur(spec);
    case ToolKind::Handpiece: return handpiece();
    case ToolKind::Mirror: return mirror();
  }
  return {};
}

double burRadiusAt(const ToolSpec& spec, double height_mm) {
  if (!isBur(spec.kind) || !(height_mm >= 0.0) || height_mm > spec.cutting_length_mm) return 0.0;
  const double r = 0.5 * spec.head_diameter_mm;
  switch (spec.kind) {
    case ToolKind::RoundBur:
    case ToolKind::FissureBur: {
      // The ball (a round bur's whole head, a fissure bur's end) up to its equator, then the cylinder.
      if (spec.kind == ToolKind::FissureBur && height_mm >= r) return r;
      const double dz = height_mm - r;
      return std::sqrt(std::max(0.0, r * r - dz * dz));
    }
    case ToolKind::ChamferBur:
    case ToolKind::ShoulderBur: return TaperedHead(spec).radiusAt(height_mm);
    default: return 0.0;
  }
}

std::string toolCatalogJson() {
  std::string j = "{\n  \"units\": \"mm\",\n  \"tools\": [\n";
  const auto tools = toolCatalog();
  for (size_t i = 0; i < tools.size(); ++i) {
    const ToolSpec& t = tools[i];
    const bool bur = isBur(t.kind);
    char line[512];
    std::snprintf(line, sizeof line, "    {\"name\": \"%s\", \"file\": \"%s.stl\", \"kind\": \"%s\", \"head_diameter_mm\": %.1f",
                  t.name, t.name, toolKindName(t.kind), t.head_diameter_mm);
    j += line;
    if (bur) {
      std::snprintf(line, sizeof line,
                    ", \"tip_diameter_mm\": %.3f, \"cutting_length_mm\": %.1f, \"shank_diameter_mm\": %.1f, \"length_mm\": %.1f",
                    t.tip_diameter_mm, t.cutting_length_mm, 2.0 * kShankRadius, kBurLength);
      j += line;
    }
    j += i + 1 < tools.size() ? "},\n" : "}\n";
  }
  j += "  ]\n}\n";
  return j;
}

}  // namespace dentsim
