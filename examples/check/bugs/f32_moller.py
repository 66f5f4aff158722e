#!/usr/bin/env python3
"""exact.py with one classic bug: the triangle by Möller–Trumbore in f32.

python3 f32_moller.py scene.txt rays.txt

The bug: the triangle's det, u, v and t are computed in single precision, every operation
rounded to the nearest f32 (emulated here by packing each result into 4 bytes), as C's float
or the lecture's GLSL would. Each triangle rounds its own u, v and u + v, so a ray through an
edge two triangles share can slip between them (a leak) or hit both (the nearer then decided
by rounded t's); det underflows for tiny triangles. Spheres stay exact rationals.
"""
import sys
from fractions import Fraction as Q
from math import isqrt
import math
import struct


def sqrt(x):  # exact where x is a square, else within 2^-200 relative
    n, d = x.numerator * x.denominator, x.denominator
    r = isqrt(n)
    return Q(r, d) if r * r == n else Q(isqrt(n << 400), d << 200)


def sub(a, b): return [x - y for x, y in zip(a, b)]
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def cross(a, b): return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def f(x):  # x rounded to the nearest f32 (beyond f32's range: ±inf)
    try:
        return struct.unpack("f", struct.pack("f", x))[0]
    except OverflowError:
        return math.copysign(math.inf, x)


def sub32(a, b): return [f(x - y) for x, y in zip(a, b)]
def dot32(a, b): return f(f(f(a[0] * b[0]) + f(a[1] * b[1])) + f(a[2] * b[2]))
def cross32(a, b): return [f(f(a[i] * b[j]) - f(a[j] * b[i])) for i, j in ((1, 2), (2, 0), (0, 1))]


def moller_trumbore_f32(v, o, d):  # o + t·d = v0 + u·e1 + v·e2, all in f32 (closed, edge-on misses)
    e1, e2, s = sub32(v[3:6], v[:3]), sub32(v[6:], v[:3]), sub32(o, v[:3])
    p = cross32(d, e2)
    det = dot32(e1, p)
    if det == 0:
        return []
    inv_det = f(1 / det)
    u = f(dot32(s, p) * inv_det)
    if u < 0 or u > 1:
        return []
    q = cross32(s, e1)
    w = f(dot32(d, q) * inv_det)
    if w < 0 or f(u + w) > 1:
        return []
    t = f(dot32(e2, q) * inv_det)
    return [] if math.isnan(t) else [t]


PRECISION = sys.argv[3] if len(sys.argv) > 3 else "f32"  # a third argument f64 reads in double


def num(word):  # the number as raylab reads it: the nearest f32 (or f64) value, ties to even
    x = Q(word)
    if PRECISION == "f64" or x == 0:
        return Q(float(x))  # (float of a Fraction rounds correctly)
    a = abs(x)
    e = a.numerator.bit_length() - a.denominator.bit_length()  # 2^(e-1) < a < 2^(e+1)
    ulp = max(e - 24 + (a >= Q(2) ** e), -149)  # f32's 24 bits, subnormals' 2^-149
    m = a / Q(2) ** ulp
    n, r = divmod(m.numerator, m.denominator)
    n += 2 * r > m.denominator or (2 * r == m.denominator and n % 2 == 1)
    return (1 if x > 0 else -1) * n * Q(2) ** ulp


def hits(kind, v, o, d):  # the ray parameters where o + t·d meets the primitive
    if kind == "tri":  # BUG: Möller–Trumbore with every operation rounded to f32
        return moller_trumbore_f32([float(x) for x in v], [float(x) for x in o], [float(x) for x in d])
    oc = sub(o, v[:3])  # |o + t·d − c|² = r²: a·t² + 2b·t + c = 0 (a tangent touch hits)
    a, b, c = dot(d, d), dot(d, oc), dot(oc, oc) - v[3] ** 2
    disc = b * b - a * c
    return [] if disc < 0 else [(-b - sqrt(disc)) / a, (-b + sqrt(disc)) / a]


shapes = [(w[0], [num(x) for x in w[1:]]) for w in map(str.split, open(sys.argv[1])) if w and w[0] in ("tri", "sphere")]
for w in map(str.split, open(sys.argv[2])):
    if not w or w[0].startswith("#"):
        continue
    o, d = [num(x) for x in w[:3]], [num(x) for x in w[3:6]]
    tmin = -Q(10) ** 5000 if w[6] == "-inf" else num(w[6])  # (below any t a ray can have)
    best, tmax = None, None if w[7] == "inf" else num(w[7])
    for i, (kind, v) in enumerate(shapes):  # strictly nearer only: an exact tie keeps the lower index
        t = next((t for t in hits(kind, v, o, d) if tmin < t and (tmax is None or t < tmax)), None)
        if t is not None:
            best, tmax = (t, i), t
    print(f"hit {float(best[0])!r} {best[1]}" if best else "miss")
