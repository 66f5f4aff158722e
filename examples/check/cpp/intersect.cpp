// Nearest hits with the lecture's formulas in double: ./intersect scene.txt rays.txt
//
// Build:  g++ -O2 -std=c++17 -o intersect intersect.cpp
// Check:  raylab check --suite DIR --program './intersect {scene} {rays}' --precision f64
//
// A starter for the lab in C++: it reads the `raylab trace` formats, answers every ray with
// the plain formulas (Cramer's rule for the triangle, the quadratic for the sphere) and prints
// `hit <t> <index>` or `miss` per ray. It is not exact: `raylab check` shows where double
// rounding still decides a hit. Standard library only.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

struct Vec3 {
    double x, y, z;
};

static Vec3 sub(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
static Vec3 scale(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
static double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

struct Primitive {
    bool is_sphere;
    Vec3 v0, v1, v2;  // a triangle's vertices
    Vec3 c;           // a sphere's centre ...
    double r;         // ... and radius
};

// Every number with std::strtod: it reads any decimal exactly rounded, and `inf`, `-inf`.
// (std::stof would round to float, and throws on words it cannot read.)
static bool numbers(std::istringstream& words, double* out, int n) {
    std::string w;
    for (int i = 0; i < n; i++) {
        if (!(words >> w)) return false;
        char* end = nullptr;
        out[i] = std::strtod(w.c_str(), &end);
        if (end == w.c_str() || *end != '\0') return false;
    }
    return !(words >> w);  // nothing after the last number
}

// Lines that carry data: not blank, not a `#` comment.
static bool data_line(const std::string& line) {
    size_t first = line.find_first_not_of(" \t\r");
    return first != std::string::npos && line[first] != '#';
}

// The ray o + t·d meets the triangle v0 v1 v2 where
//     o + t·d = v0 + u·e1 + v·e2,   e1 = v1 − v0, e2 = v2 − v0,
// a 3×3 system A·(t, u, v) = s with A = [−d e1 e2] and s = o − v0, solved by Cramer's rule,
// each determinant a triple product (the Möller–Trumbore form):
//     det = e1 · (d × e2)
//     u   = s · (d × e2) / det
//     v   = d · (s × e1) / det
//     t   = e2 · (s × e1) / det
// The triangle is two-sided (det of either sign) and closed: u ≥ 0, v ≥ 0, u + v ≤ 1, edges and
// vertices included. A ray in the triangle's plane (det = 0) misses.
static bool hit_triangle(const Primitive& p, Vec3 o, Vec3 d, double& t) {
    Vec3 e1 = sub(p.v1, p.v0), e2 = sub(p.v2, p.v0), s = sub(o, p.v0);
    Vec3 pv = cross(d, e2);  // d × e2
    double det = dot(e1, pv);
    if (det == 0) return false;
    Vec3 qv = cross(s, e1);  // s × e1
    double u = dot(s, pv) / det;
    double v = dot(d, qv) / det;
    if (!(u >= 0 && v >= 0 && u + v <= 1)) return false;
    t = dot(e2, qv) / det;
    return true;
}

// The ray meets the sphere where |o + t·d − c|² = r²:
//     a·t² + 2b'·t + c' = 0,   a = d·d, b' = d·(o − c), c' = |o − c|² − r².
// The textbook discriminant b'² − a·c' cancels when the ray passes near the rim or the sphere
// is far away (both terms are huge and nearly equal). The stable form measures the ray's
// distance from the centre instead: h = (o − c) − (b'/a)·d is the perpendicular from the
// centre to the ray's line, and
//     disc = a·(r² − |h|²)
// (the same value in exact arithmetic: b'² − a·c' = a·(r² − |h|²)). A tangent ray (disc = 0)
// hits. The roots without cancelling −b' against sqrt(disc):
//     q = −b' − sign(b')·sqrt(disc),   t0 = q/a,   t1 = c'/q   (t0·t1 = c'/a).
// Returns the roots in increasing order.
static bool hit_sphere(const Primitive& p, Vec3 o, Vec3 d, double& t0, double& t1) {
    Vec3 oc = sub(o, p.c);
    double a = dot(d, d);
    double b = dot(d, oc);  // b'
    Vec3 h = sub(oc, scale(b / a, d));
    double disc = a * (p.r * p.r - dot(h, h));
    if (disc < 0) return false;
    double c = dot(oc, oc) - p.r * p.r;  // c'
    double q = b >= 0 ? -b - std::sqrt(disc) : -b + std::sqrt(disc);
    t0 = q / a;
    t1 = q != 0 ? c / q : t0;  // q = 0: b' = 0 and disc = 0, one root (t = 0)
    if (t1 < t0) std::swap(t0, t1);
    return true;
}

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s scene.txt rays.txt\n", argv[0]);
        return 2;
    }
    std::ifstream scene_file(argv[1]), rays_file(argv[2]);
    if (!scene_file || !rays_file) {
        std::fprintf(stderr, "cannot open %s\n", !scene_file ? argv[1] : argv[2]);
        return 2;
    }

    // The scene: `tri x0 y0 z0 x1 y1 z1 x2 y2 z2` or `sphere cx cy cz r` per line; a
    // primitive's index is its position among the primitives.
    std::vector<Primitive> prims;
    std::string line;
    for (int n = 1; std::getline(scene_file, line); n++) {
        if (!data_line(line)) continue;
        std::istringstream words(line);
        std::string kind;
        words >> kind;
        double x[9];
        Primitive p{};
        if (kind == "tri" && numbers(words, x, 9)) {
            p.v0 = {x[0], x[1], x[2]};
            p.v1 = {x[3], x[4], x[5]};
            p.v2 = {x[6], x[7], x[8]};
        } else if (kind == "sphere" && numbers(words, x, 4)) {
            p.is_sphere = true;
            p.c = {x[0], x[1], x[2]};
            p.r = x[3];
        } else {
            std::fprintf(stderr, "%s:%d: expected a triangle or a sphere\n", argv[1], n);
            return 2;
        }
        prims.push_back(p);
    }

    // The rays: `ox oy oz dx dy dz tmin tmax`, the points o + t·d with tmin < t < tmax (both
    // ends open; tmax may be inf). d is used as given, not normalised: t is in units of d.
    for (int n = 1; std::getline(rays_file, line); n++) {
        if (!data_line(line)) continue;
        std::istringstream words(line);
        double x[8];
        if (!numbers(words, x, 8)) {
            std::fprintf(stderr, "%s:%d: a ray needs 8 numbers\n", argv[2], n);
            return 2;
        }
        Vec3 o{x[0], x[1], x[2]}, d{x[3], x[4], x[5]};
        double tmin = x[6], tmax = x[7];

        // The closest hit: every primitive, keeping the one met nearest inside (tmin, tmax).
        // Only a strictly nearer hit replaces the best, so an exact tie keeps the lower index.
        long best = -1;
        double best_t = tmax;
        for (size_t i = 0; i < prims.size(); i++) {
            const Primitive& p = prims[i];
            double t, t1;
            if (p.is_sphere) {
                if (!hit_sphere(p, o, d, t, t1)) continue;
                if (!(tmin < t)) t = t1;  // the near root is behind tmin: the far one
            } else if (!hit_triangle(p, o, d, t)) {
                continue;
            }
            if (tmin < t && t < best_t) {
                best = static_cast<long>(i);
                best_t = t;
            }
        }
        // %.17g: enough digits that the double reads back to the same bits.
        if (best < 0) {
            std::printf("miss\n");
        } else {
            std::printf("hit %.17g %ld\n", best_t, best);
        }
    }
    return 0;
}
