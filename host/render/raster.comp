#version 450
// GPU twin of the CPU rasteriser (host/render/rasterizer.cpp): a z-buffered, flat-shaded,
// 2×2-supersampled orthographic render of a triangle mesh, as a compute shader so that it runs
// on the project's compute queue (a dedicated compute queue on a real GPU cannot draw) and
// follows the CPU twin's rules exactly rather than the fixed-function rasteriser's:
//   pass 0 clear    one invocation per sample: depth = far, winner = none
//   pass 1 depth    one invocation per face: set-up (projection, shading), then every covered
//                   sample takes atomicMin(depth, key(z)), key the float's order as a uint
//   pass 2 winner   one invocation per face: where its key equals the sample's depth,
//                   atomicMin(winner, face) — the nearest face wins, ties to the lower index,
//                   as in the CPU twin, whatever the scheduling
//   pass 3 resolve  one invocation per pixel: the 2×2 box filter of the winners' colours
// setup() and raster() mirror project() and rasterize_band() in rasterizer.cpp line by line, in
// double, `precise` (no contraction); change one twin, change the other
// (tests/host/render/rasterizer_vk_test.cpp compares them).
layout(local_size_x_id = 0) in;

layout(std430, set = 0, binding = 0) readonly buffer ViewBlock {
  double centre[3];
  double right[3];
  double up[3];
  double forward[3];
  double light[3];
  double scale;
  int sw;  // supersampled size
  int sh;
  int width;  // picture size
  int height;
  uint background;  // 0xFFRRGGBB
  uint face_count;
} view;
layout(std430, set = 0, binding = 1) readonly buffer Vertices { double vertices[]; };  // #V×3
layout(std430, set = 0, binding = 2) readonly buffer Faces { int faces[]; };           // #F×3
layout(std430, set = 0, binding = 3) readonly buffer Colours { double colours[]; };    // #F×3 rgb
layout(std430, set = 0, binding = 4) buffer Shaded { uint shaded[]; };                 // #F packed
layout(std430, set = 0, binding = 5) buffer Depth { uint depth[]; };                   // sw×sh keys
layout(std430, set = 0, binding = 6) buffer Winner { uint winner[]; };                 // sw×sh faces
layout(std430, set = 0, binding = 7) writeonly buffer Pixels { uint pixels[]; };       // w×h

layout(push_constant, std430) uniform Push {
  uint first;  // DispatchRange
  uint count;
  uint pass;
  uint pad;
} pc;

const uint kPassClear = 0u;
const uint kPassDepth = 1u;
const uint kPassWinner = 2u;
const uint kPassResolve = 3u;
const int kSupersample = 2;
const uint kFar = 0xFF800000u;  // depth_key(+inf): the CPU twin's empty depth, never beaten by +inf
const uint kNone = 0xFFFFFFFFu;

// A float's order as an unsigned int (negative: all bits flipped; positive: sign bit set), so
// that atomicMin on keys is min on depths. −0 is +0 first: the CPU twin's `<` treats them equal.
uint depth_key(float z) {
  const uint bits = floatBitsToUint(z == 0.0 ? 0.0 : z);
  return (bits & 0x80000000u) != 0u ? ~bits : (bits | 0x80000000u);
}

dvec3 view_vec(const double v[3]) { return dvec3(v[0], v[1], v[2]); }

double dot3(dvec3 a, dvec3 b) {
  precise double s = a.x * b.x + a.y * b.y + a.z * b.z;
  return s;
}

dvec3 corner(int f, int k) {
  const int v = faces[3 * f + k];
  return dvec3(vertices[3 * v], vertices[3 * v + 1], vertices[3 * v + 2]);
}

uint channel(double v) {
  precise double s = floor(clamp(v, 0.0lf, 1.0lf) * 255.0lf + 0.5lf);
  return uint(s);
}

// The face's colour shaded by 0.35 + 0.65·|n̂ · light| (project() in rasterizer.cpp).
uint shade(int f, dvec3 p0, dvec3 p1, dvec3 p2) {
  precise dvec3 a = p1 - p0;
  precise dvec3 b = p2 - p0;
  precise dvec3 n = dvec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
  precise double len = sqrt(dot3(n, n));
  precise double lambert = len > 0.0lf ? abs(dot3(n, view_vec(view.light))) / len : 0.0lf;
  precise double s = 0.35lf + 0.65lf * lambert;
  precise double r = colours[3 * f] * s;
  precise double g = colours[3 * f + 1] * s;
  precise double bl = colours[3 * f + 2] * s;
  return 0xFF000000u | (channel(r) << 16) | (channel(g) << 8) | channel(bl);
}

// Passes 1 and 2: project face f, then visit the samples it covers.
void raster(int f, bool depth_pass) {
  const dvec3 p0 = corner(f, 0), p1 = corner(f, 1), p2 = corner(f, 2);
  if (depth_pass) shaded[f] = shade(f, p0, p1, p2);
  const dvec3 c = view_vec(view.centre), right = view_vec(view.right), up = view_vec(view.up);
  const dvec3 fwd = view_vec(view.forward);
  precise dvec3 d0 = p0 - c;
  precise dvec3 d1 = p1 - c;
  precise dvec3 d2 = p2 - c;
  precise double hw = 0.5lf * double(view.sw);
  precise double hh = 0.5lf * double(view.sh);
  precise dvec3 x = dvec3(hw + view.scale * dot3(d0, right), hw + view.scale * dot3(d1, right),
                          hw + view.scale * dot3(d2, right));
  precise dvec3 y = dvec3(hh - view.scale * dot3(d0, up), hh - view.scale * dot3(d1, up),
                          hh - view.scale * dot3(d2, up));
  precise dvec3 z = dvec3(dot3(d0, fwd), dot3(d1, fwd), dot3(d2, fwd));
  precise double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
  if (abs(area) < 1e-12lf) return;
  // The sample box, clamped in double before converting (as the CPU twin does).
  const double xa = max(0.0lf, floor(min(min(x[0], x[1]), x[2])));
  const double xb = min(double(view.sw - 1), ceil(max(max(x[0], x[1]), x[2])));
  const double ya = max(0.0lf, floor(min(min(y[0], y[1]), y[2])));
  const double yb = min(double(view.sh - 1), ceil(max(max(y[0], y[1]), y[2])));
  if (xa > xb || ya > yb) return;
  for (int sy = int(ya); sy <= int(yb); ++sy) {
    precise double py = double(sy) + 0.5lf;
    for (int sx = int(xa); sx <= int(xb); ++sx) {
      precise double px = double(sx) + 0.5lf;
      // Barycentric weights from edge functions (k: i = k+1, j = k+2), signed by the orientation.
      precise double w0 = ((x[2] - x[1]) * (py - y[1]) - (y[2] - y[1]) * (px - x[1])) / area;
      precise double w1 = ((x[0] - x[2]) * (py - y[2]) - (y[0] - y[2]) * (px - x[2])) / area;
      precise double w2 = ((x[1] - x[0]) * (py - y[0]) - (y[1] - y[0]) * (px - x[0])) / area;
      if (w0 < 0.0lf || w1 < 0.0lf || w2 < 0.0lf) continue;
      precise double zd = w0 * z[0] + w1 * z[1] + w2 * z[2];
      const float zf = float(zd);
      if (isnan(zf)) continue;
      const uint key = depth_key(zf);
      if (key >= kFar) continue;
      const uint at = uint(sy) * uint(view.sw) + uint(sx);
      if (depth_pass) {
        atomicMin(depth[at], key);
      } else if (depth[at] == key) {
        atomicMin(winner[at], uint(f));
      }
    }
  }
}

// Pass 3: the box filter over the pixel's samples, channel by channel, rounded half up.
void resolve(uint pixel) {
  const uint px = pixel % uint(view.width), py = pixel / uint(view.width);
  uvec3 sum = uvec3(0u);
  for (int dy = 0; dy < kSupersample; ++dy) {
    for (int dx = 0; dx < kSupersample; ++dx) {
      const uint s = (py * uint(kSupersample) + uint(dy)) * uint(view.sw) + px * uint(kSupersample) + uint(dx);
      const uint w = winner[s];
      const uint c = w == kNone ? view.background : shaded[w];
      sum += uvec3((c >> 16) & 0xFFu, (c >> 8) & 0xFFu, c & 0xFFu);
    }
  }
  const uint n = uint(kSupersample * kSupersample);
  const uvec3 avg = (sum + uvec3(n / 2u)) / n;
  pixels[pixel] = 0xFF000000u | (avg.r << 16) | (avg.g << 8) | avg.b;
}

void main() {
  const uint local_index = gl_GlobalInvocationID.x;
  if (local_index >= pc.count) return;
  const uint item = pc.first + local_index;
  if (pc.pass == kPassClear) {
    depth[item] = kFar;
    winner[item] = kNone;
  } else if (pc.pass == kPassDepth || pc.pass == kPassWinner) {
    raster(int(item), pc.pass == kPassDepth);
  } else if (pc.pass == kPassResolve) {
    resolve(item);
  }
}
