// The coordinate networks' jet (networks.py) as two C++ calls: one forward, one backward,
// matrix products included, for both sub-networks; and the paper's loss (Winslow, boundary
// and data terms) with its gradients in one call (``loss_net``).
//
// A jet carries, per point and neuron, six channels: the value and its derivatives d_xi,
// d_eta, d_xixi, d_xieta, d_etaeta. Jet points hold six rows each (one per channel),
// value-only points (boundary and auxiliary-line samples) one row each. Rows are padded to
// NP neurons (a multiple of 8) so that every row is whole vectors; the padding stays zero in
// the weights and never reaches an output.
//
// The work runs in blocks of rows (8 jet points, or 48 value-only points) through all layers
// at once, so a block's activations stay in the first-level cache; what backward needs is
// written to a workspace the caller owns (``net_workspace`` elements per sub-network).
// Forward per layer: z = h W (+ b on value rows), a = jet of sigma(z) (chain rule), and for
// the shortcut network h = U + a (V - U) (Leibniz rule); backward runs the same in reverse.
//
// Built by native.py with the system C++ compiler (-O3 -march=native); no Python or torch
// headers needed. GCC/Clang vector extensions give the small matrix products their registers.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <thread>
#include <type_traits>
#include <vector>

namespace {

using idx = std::ptrdiff_t;

enum Activation { TANH = 0, SIN = 1, SIGMOID = 2, SWISH = 3 };
constexpr idx POINTS = 8;   // jet points per block (48 rows)
constexpr idx ROWS = 48;    // value-only points per block

template <typename T>
struct Vec;  // 32-byte vectors, unaligned loads and stores
template <>
struct Vec<float> {
    typedef float type __attribute__((vector_size(32), aligned(4), may_alias));
    static constexpr idx L = 8;
};
template <>
struct Vec<double> {
    typedef double type __attribute__((vector_size(32), aligned(8), may_alias));
    static constexpr idx L = 4;
};

// ---- activations ----------------------------------------------------------------------

// tanh in float, written so that the compiler vectorises it (Cephes tanhf and expf, about
// 2 ulp): an odd polynomial below 0.625, (1 - e) / (1 + e) with e = exp(-2|x|) above.
inline float tanh_f(float x) {
    const float ax = std::fabs(x), s = x * x;
    const float small = ((((-5.70498872745e-3f * s + 2.06390887954e-2f) * s
                           - 5.37397155531e-2f) * s + 1.33314422036e-1f) * s
                         - 3.33332819422e-1f) * s * x + x;
    const float y = std::max(-2.0f * ax, -87.0f);
    const float fn = std::floor(y * 1.44269504088896341f + 0.5f);
    const float r = y - fn * 0.693359375f + fn * 2.12194440e-4f;
    const float p = (((((1.9875691500e-4f * r + 1.3981999507e-3f) * r + 8.3334519073e-3f) * r
                       + 4.1665795894e-2f) * r + 1.6666665459e-1f) * r + 5.0000001201e-1f)
                    * r * r + r + 1.0f;
    const float e = p * __builtin_bit_cast(float, (static_cast<int>(fn) + 127) << 23);
    const float large = std::copysign((1.0f - e) / (1.0f + e), x);
    return ax < 0.625f ? small : large;
}

inline float tanh_any(float x) { return tanh_f(x); }
inline double tanh_any(double x) { return std::tanh(x); }

// p = sigma-like primary function of z (tanh, sin, sigmoid; swish uses sigmoid) and
// q = cos(z) for the sine, over n elements.
template <typename T, int A>
void primary(idx n, const T *__restrict z, T *__restrict p, T *__restrict q) {
    if (A == TANH) {
        for (idx e = 0; e < n; ++e) p[e] = tanh_any(z[e]);
    } else if (A == SIN) {
        for (idx e = 0; e < n; ++e) { p[e] = std::sin(z[e]); q[e] = std::cos(z[e]); }
    } else {
        for (idx e = 0; e < n; ++e) p[e] = T(1) / (T(1) + std::exp(-z[e]));
    }
}

// sigma(z) and its first three derivatives from z, p and q.
template <typename T, int A>
inline void derivatives(T z, T p, T q, T &s, T &d1, T &d2, T &d3) {
    if (A == TANH) {
        s = p; d1 = 1 - p * p; d2 = -2 * p * d1; d3 = -2 * (d1 * d1 + p * d2);
    } else if (A == SIN) {
        s = p; d1 = q; d2 = -p; d3 = -q;
    } else if (A == SIGMOID) {
        s = p; d1 = p * (1 - p); d2 = d1 * (1 - 2 * p); d3 = d2 * (1 - 2 * p) - 2 * d1 * d1;
    } else {  // swish: z * sigmoid(z)
        T g1 = p * (1 - p), g2 = g1 * (1 - 2 * p), g3 = g2 * (1 - 2 * p) - 2 * g1 * g1;
        s = z * p; d1 = p + z * g1; d2 = 2 * g1 + z * g2; d3 = 3 * g2 + z * g3;
    }
}

// ---- small matrix products -------------------------------------------------------------

// C (rows x NP) = A (rows x NP, first n columns used) times W (n x NP).
template <typename T, int NP>
void matmul(idx rows, idx n, const T *__restrict a, const T *__restrict w, T *__restrict c) {
    using V = typename Vec<T>::type;
    constexpr idx NV = NP / Vec<T>::L, RB = NV >= 16 ? 1 : NV >= 8 ? 3 : NV >= 4 ? 6 : 12;
    idx r = 0;
    for (; r + RB <= rows; r += RB) {
        V acc[RB][NV];
        for (idx rr = 0; rr < RB; ++rr)
            for (idx v = 0; v < NV; ++v) acc[rr][v] = V{} ;
        for (idx i = 0; i < n; ++i) {
            const V *wv = reinterpret_cast<const V *>(w + i * NP);
            for (idx rr = 0; rr < RB; ++rr) {
                const T x = a[(r + rr) * NP + i];
                for (idx v = 0; v < NV; ++v) acc[rr][v] += x * wv[v];
            }
        }
        for (idx rr = 0; rr < RB; ++rr)
            for (idx v = 0; v < NV; ++v) reinterpret_cast<V *>(c + (r + rr) * NP)[v] = acc[rr][v];
    }
    for (; r < rows; ++r) {
        V acc[NV];
        for (idx v = 0; v < NV; ++v) acc[v] = V{};
        for (idx i = 0; i < n; ++i) {
            const V *wv = reinterpret_cast<const V *>(w + i * NP);
            const T x = a[r * NP + i];
            for (idx v = 0; v < NV; ++v) acc[v] += x * wv[v];
        }
        for (idx v = 0; v < NV; ++v) reinterpret_cast<V *>(c + r * NP)[v] = acc[v];
    }
}

// G (n x NP) += A^T (n x rows) times D (rows x NP): a weight matrix's gradient.
template <typename T, int NP>
void outer(idx rows, idx n, const T *__restrict a, const T *__restrict d, T *__restrict g) {
    using V = typename Vec<T>::type;
    constexpr idx NV = NP / Vec<T>::L, IB = NV >= 16 ? 1 : NV >= 8 ? 3 : NV >= 4 ? 6 : 12;
    idx i = 0;
    for (; i + IB <= n; i += IB) {
        V acc[IB][NV];
        for (idx ii = 0; ii < IB; ++ii)
            for (idx v = 0; v < NV; ++v) acc[ii][v] = reinterpret_cast<V *>(g + (i + ii) * NP)[v];
        for (idx r = 0; r < rows; ++r) {
            const V *dv = reinterpret_cast<const V *>(d + r * NP);
            for (idx ii = 0; ii < IB; ++ii) {
                const T x = a[r * NP + i + ii];
                for (idx v = 0; v < NV; ++v) acc[ii][v] += x * dv[v];
            }
        }
        for (idx ii = 0; ii < IB; ++ii)
            for (idx v = 0; v < NV; ++v) reinterpret_cast<V *>(g + (i + ii) * NP)[v] = acc[ii][v];
    }
    for (; i < n; ++i) {
        V acc[NV];
        for (idx v = 0; v < NV; ++v) acc[v] = reinterpret_cast<V *>(g + i * NP)[v];
        for (idx r = 0; r < rows; ++r) {
            const V *dv = reinterpret_cast<const V *>(d + r * NP);
            const T x = a[r * NP + i];
            for (idx v = 0; v < NV; ++v) acc[v] += x * dv[v];
        }
        for (idx v = 0; v < NV; ++v) reinterpret_cast<V *>(g + i * NP)[v] = acc[v];
    }
}

// ---- one layer's activation on a block ---------------------------------------------------

// Jet rows: block of P points, six rows each; z rows hold the pre-activation jet (the
// value row without its bias yet when ``bias`` is given). Writes a (6 rows a point) and
// d = sigma', sigma'', sigma''' (3 rows a point). For an input layer (z1 = W row 0,
// z2 = W row 1, second derivatives zero) pass z = nullptr, the value rows in z0 (one a
// point) and the two weight rows in w0, w1.
template <typename T, int A, bool INPUT>
void act_jet(idx P, idx np, const T *z, const T *z0in, const T *w0, const T *w1,
             const T *bias, T *buf, T *a, T *d) {
    T *z0 = buf, *p = buf + P * np, *q = buf + 2 * P * np;
    for (idx k = 0; k < P; ++k) {
        const T *src = INPUT ? z0in + k * np : z + 6 * k * np;
        for (idx j = 0; j < np; ++j) z0[k * np + j] = src[j] + bias[j];
    }
    primary<T, A>(P * np, z0, p, q);
    for (idx k = 0; k < P; ++k) {
        const T *Z = INPUT ? nullptr : z + 6 * k * np;
        T *Ao = a + 6 * k * np, *D = d + 3 * k * np;
        const T *Z0 = z0 + k * np, *Pk = p + k * np, *Qk = q + k * np;
#pragma GCC ivdep
        for (idx j = 0; j < np; ++j) {
            T s, d1, d2, d3;
            derivatives<T, A>(Z0[j], Pk[j], Qk[j], s, d1, d2, d3);
            const T z1 = INPUT ? w0[j] : Z[np + j], z2 = INPUT ? w1[j] : Z[2 * np + j];
            const T z3 = INPUT ? T(0) : Z[3 * np + j], z4 = INPUT ? T(0) : Z[4 * np + j];
            const T z5 = INPUT ? T(0) : Z[5 * np + j];
            Ao[j] = s; Ao[np + j] = d1 * z1; Ao[2 * np + j] = d1 * z2;
            Ao[3 * np + j] = d2 * z1 * z1 + d1 * z3;
            Ao[4 * np + j] = d2 * z1 * z2 + d1 * z4;
            Ao[5 * np + j] = d2 * z2 * z2 + d1 * z5;
            D[j] = d1; D[np + j] = d2; D[2 * np + j] = d3;
        }
    }
}

// Value rows: a = sigma(z + bias), d = sigma'.
template <typename T, int A>
void act_val(idx rows, idx np, const T *z, const T *bias, T *buf, T *a, T *d) {
    T *z0 = buf, *p = buf + rows * np, *q = buf + 2 * rows * np;
    for (idx r = 0; r < rows; ++r)
        for (idx j = 0; j < np; ++j) z0[r * np + j] = z[r * np + j] + bias[j];
    primary<T, A>(rows * np, z0, p, q);
#pragma GCC ivdep
    for (idx e = 0; e < rows * np; ++e) {
        T s, d1, d2, d3;
        derivatives<T, A>(z0[e], p[e], q[e], s, d1, d2, d3);
        a[e] = s; d[e] = d1;
    }
}

// Reverse of act_jet: c = dL/da (6 rows a point) -> dz = dL/dz.
template <typename T, bool INPUT>
void act_jet_back(idx P, idx np, const T *c, const T *z, const T *w0, const T *w1,
                  const T *d, T *dz) {
    for (idx k = 0; k < P; ++k) {
        const T *C = c + 6 * k * np, *Z = INPUT ? nullptr : z + 6 * k * np, *D = d + 3 * k * np;
        T *DZ = dz + 6 * k * np;
#pragma GCC ivdep
        for (idx j = 0; j < np; ++j) {
            const T c0 = C[j], c1 = C[np + j], c2 = C[2 * np + j];
            const T c3 = C[3 * np + j], c4 = C[4 * np + j], c5 = C[5 * np + j];
            const T z1 = INPUT ? w0[j] : Z[np + j], z2 = INPUT ? w1[j] : Z[2 * np + j];
            const T z3 = INPUT ? T(0) : Z[3 * np + j], z4 = INPUT ? T(0) : Z[4 * np + j];
            const T z5 = INPUT ? T(0) : Z[5 * np + j];
            const T d1 = D[j], d2 = D[np + j], d3 = D[2 * np + j];
            const T gd1 = c1 * z1 + c2 * z2 + c3 * z3 + c4 * z4 + c5 * z5;
            const T gd2 = (c3 * z1 + c4 * z2) * z1 + c5 * z2 * z2;
            DZ[j] = c0 * d1 + gd1 * d2 + gd2 * d3;
            DZ[np + j] = c1 * d1 + d2 * (2 * c3 * z1 + c4 * z2);
            DZ[2 * np + j] = c2 * d1 + d2 * (c4 * z1 + 2 * c5 * z2);
            DZ[3 * np + j] = c3 * d1; DZ[4 * np + j] = c4 * d1; DZ[5 * np + j] = c5 * d1;
        }
    }
}

// h = u + a * w on jets (Leibniz rule), P points.
template <typename T>
void gate_jet(idx P, idx np, const T *u, const T *a, const T *w, T *h) {
    for (idx k = 0; k < P; ++k) {
        const T *U = u + 6 * k * np, *Ai = a + 6 * k * np, *W = w + 6 * k * np;
        T *H = h + 6 * k * np;
#pragma GCC ivdep
        for (idx j = 0; j < np; ++j) {
            const T w0 = W[j], w1 = W[np + j], w2 = W[2 * np + j];
            const T a0 = Ai[j], a1 = Ai[np + j], a2 = Ai[2 * np + j];
            H[j] = U[j] + a0 * w0;
            H[np + j] = U[np + j] + a1 * w0 + a0 * w1;
            H[2 * np + j] = U[2 * np + j] + a2 * w0 + a0 * w2;
            H[3 * np + j] = U[3 * np + j] + Ai[3 * np + j] * w0 + 2 * a1 * w1 + a0 * W[3 * np + j];
            H[4 * np + j] = U[4 * np + j] + Ai[4 * np + j] * w0 + a1 * w2 + a2 * w1
                            + a0 * W[4 * np + j];
            H[5 * np + j] = U[5 * np + j] + Ai[5 * np + j] * w0 + 2 * a2 * w2 + a0 * W[5 * np + j];
        }
    }
}

// Reverse of gate_jet: g = dL/dh -> c = dL/da; adds dL/dw to gw (dL/du is g itself).
template <typename T>
void gate_jet_back(idx P, idx np, const T *g, const T *a, const T *w, T *c, T *gw) {
    for (idx k = 0; k < P; ++k) {
        const T *G = g + 6 * k * np, *Ai = a + 6 * k * np, *W = w + 6 * k * np;
        T *C = c + 6 * k * np, *GW = gw + 6 * k * np;
#pragma GCC ivdep
        for (idx j = 0; j < np; ++j) {
            const T g0 = G[j], g1 = G[np + j], g2 = G[2 * np + j];
            const T g3 = G[3 * np + j], g4 = G[4 * np + j], g5 = G[5 * np + j];
            const T w0 = W[j], w1 = W[np + j], w2 = W[2 * np + j];
            const T a0 = Ai[j], a1 = Ai[np + j], a2 = Ai[2 * np + j];
            C[j] = g0 * w0 + g1 * w1 + g2 * w2 + g3 * W[3 * np + j] + g4 * W[4 * np + j]
                   + g5 * W[5 * np + j];
            C[np + j] = g1 * w0 + 2 * g3 * w1 + g4 * w2;
            C[2 * np + j] = g2 * w0 + g4 * w1 + 2 * g5 * w2;
            C[3 * np + j] = g3 * w0; C[4 * np + j] = g4 * w0; C[5 * np + j] = g5 * w0;
            GW[j] += g0 * a0 + g1 * a1 + g2 * a2 + g3 * Ai[3 * np + j] + g4 * Ai[4 * np + j]
                     + g5 * Ai[5 * np + j];
            GW[np + j] += g1 * a0 + 2 * g3 * a1 + g4 * a2;
            GW[2 * np + j] += g2 * a0 + g4 * a1 + 2 * g5 * a2;
            GW[3 * np + j] += g3 * a0; GW[4 * np + j] += g4 * a0; GW[5 * np + j] += g5 * a0;
        }
    }
}

// ---- the network -----------------------------------------------------------------------

// Shapes of one call. Parameters (per sub-network k of K, torch layout (K, in, out)):
// w_in, b_in, [w_u, b_u, w_v, b_v], then (w, b) per gated/hidden layer, then w_out, b_out.
struct Shape {
    idx K, L, n, B, E;
    bool gated;
    int threads;  // the sub-networks run on up to this many threads
};

// Workspace of one sub-network, in elements of T: per state l < L the layer output H_l
// (R rows) and sigma's derivatives D_l (3 B + E rows); per hidden layer l >= 1 its
// pre-activation Z_l and (gated) activation A_l (R rows each); gated also D_u, D_v and
// V - U (R rows).
struct Layout {
    idx np, R, RD, H, D, Z, A, Du, Dv, W, size;
    Layout(const Shape &s, idx NP) {
        np = NP;
        R = (6 * s.B + s.E) * np;
        RD = (3 * s.B + s.E) * np;
        const idx hidden = s.L - 1;
        H = 0;
        D = H + s.L * R;
        Z = D + s.L * RD;
        A = Z + hidden * R;
        Du = A + (s.gated ? hidden * R : 0);
        Dv = Du + (s.gated ? RD : 0);
        W = Dv + (s.gated ? RD : 0);
        size = W + (s.gated ? R : 0);
    }
};

template <typename T>
struct Params {  // one sub-network's parameters, padded to np columns (zeros beyond n)
    std::vector<T> w_in, b_in, w_u, b_u, w_v, b_v, w_out;
    std::vector<std::vector<T>> w, wt, b;  // hidden weights, their transposes, biases
    T b_out = 0;
};

template <typename T>
Params<T> load(const Shape &s, idx np, const T *const *param, idx k) {
    Params<T> p;
    const idx n = s.n;
    auto mat = [&](const T *src, idx rows, std::vector<T> &dst) {  // (K, rows, n) -> padded
        dst.assign(rows * np, T(0));
        for (idx i = 0; i < rows; ++i)
            for (idx j = 0; j < n; ++j) dst[i * np + j] = src[(k * rows + i) * n + j];
    };
    int at = 0;
    mat(param[at++], 2, p.w_in);
    mat(param[at++], 1, p.b_in);
    if (s.gated) {
        mat(param[at++], 2, p.w_u);
        mat(param[at++], 1, p.b_u);
        mat(param[at++], 2, p.w_v);
        mat(param[at++], 1, p.b_v);
    }
    for (idx l = 1; l < s.L; ++l) {
        std::vector<T> w, wt(np * np, T(0)), b;
        mat(param[at++], n, w);
        w.resize(np * np, T(0));
        for (idx i = 0; i < n; ++i)
            for (idx j = 0; j < n; ++j) wt[j * np + i] = w[i * np + j];
        mat(param[at++], 1, b);
        p.w.push_back(std::move(w));
        p.wt.push_back(std::move(wt));
        p.b.push_back(std::move(b));
    }
    p.w_out.assign(np, T(0));
    for (idx j = 0; j < n; ++j) p.w_out[j] = param[at][k * n + j];
    p.b_out = param[at + 1][k];
    return p;
}

template <typename T>
struct Scratch {  // one block's temporaries (ROWS rows of np)
    std::vector<T> buf, u, v, zin, dh, c, dz;
    explicit Scratch(idx np)
        : buf(3 * ROWS * np), u(ROWS * np), v(ROWS * np), zin(ROWS * np), dh(ROWS * np),
          c(ROWS * np), dz(ROWS * np) {}
};

// Forward of sub-network k over the jet points [p0, p0 + P) (jet = true) or the value-only
// points [p0, p0 + P) (jet = false).
template <typename T, int NP, int A>
void forward_block(const Shape &s, const Layout &lay, const Params<T> &p, Scratch<T> &sc,
                   idx k, bool jet, idx p0, idx P, const T *x, const T *ex, T *ws, idx off,
                   idx offd, T *jet_out, T *val_out) {
    constexpr idx np = NP;
    const idx rows = jet ? 6 * P : P;
    T *buf = sc.buf.data(), *u = sc.u.data(), *v = sc.v.data(), *zin = sc.zin.data();
    const T *pts = jet ? x + 2 * p0 : ex + 2 * p0;
    auto input = [&](const std::vector<T> &w, const std::vector<T> &b, T *out, T *d) {
        for (idx q = 0; q < P; ++q)
            for (idx j = 0; j < np; ++j)
                zin[q * np + j] = pts[2 * q] * w[j] + pts[2 * q + 1] * w[np + j];
        if (jet)
            act_jet<T, A, true>(P, np, nullptr, zin, w.data(), w.data() + np, b.data(), buf,
                                out, d);
        else
            act_val<T, A>(P, np, zin, b.data(), buf, out, d);
    };
    T *H0 = ws + lay.H + off;
    input(p.w_in, p.b_in, H0, ws + lay.D + offd);
    T *W = ws + lay.W + off;
    if (s.gated) {
        input(p.w_u, p.b_u, u, ws + lay.Du + offd);
        input(p.w_v, p.b_v, v, ws + lay.Dv + offd);
        for (idx e = 0; e < rows * np; ++e) W[e] = v[e] - u[e];
    }
    for (idx l = 1; l < s.L; ++l) {
        const T *Hp = ws + lay.H + (l - 1) * lay.R + off;
        T *Z = ws + lay.Z + (l - 1) * lay.R + off, *H = ws + lay.H + l * lay.R + off;
        T *D = ws + lay.D + l * lay.RD + offd;
        T *Aa = s.gated ? ws + lay.A + (l - 1) * lay.R + off : H;
        matmul<T, NP>(rows, s.n, Hp, p.w[l - 1].data(), Z);
        if (jet) {
            // the bias joins the value row only (backward never reads Z's value rows)
            act_jet<T, A, false>(P, np, Z, nullptr, nullptr, nullptr, p.b[l - 1].data(), buf,
                                 Aa, D);
            if (s.gated) gate_jet(P, np, u, Aa, W, H);
        } else {
            act_val<T, A>(P, np, Z, p.b[l - 1].data(), buf, Aa, D);
            if (s.gated)
                for (idx e = 0; e < rows * np; ++e) H[e] = u[e] + Aa[e] * W[e];
        }
    }
    const T *H = ws + lay.H + (s.L - 1) * lay.R + off;
    T *out = jet ? jet_out : val_out;  // null: a recomputation for backward
    for (idx r = 0; out && r < rows; ++r) {
        T acc = 0;
        for (idx j = 0; j < s.n; ++j) acc += H[r * np + j] * p.w_out[j];
        if (jet) {
            const idx q = r / 6, c = r % 6;
            jet_out[(c * s.B + p0 + q) * s.K + k] = acc + (c == 0 ? p.b_out : T(0));
        } else {
            val_out[(p0 + r) * s.K + k] = acc + p.b_out;
        }
    }
}

template <typename T>
struct Grads {  // one sub-network's gradients, padded like Params
    std::vector<T> w_in, b_in, w_u, b_u, w_v, b_v, w_out;
    std::vector<std::vector<T>> w, b;
    T b_out = 0;
    Grads(const Shape &s, idx np)
        : w_in(2 * np), b_in(np), w_u(2 * np), b_u(np), w_v(2 * np), b_v(np), w_out(np),
          w(s.L - 1, std::vector<T>(np * np)), b(s.L - 1, std::vector<T>(np)) {}
};

template <typename T, int NP>
void backward_block(const Shape &s, const Layout &lay, const Params<T> &p, Grads<T> &g,
                    Scratch<T> &sc, idx k, bool jet, idx p0, idx P, const T *x, const T *ex,
                    const T *ws, idx off, idx offd, const T *g_jet, const T *g_val) {
    constexpr idx np = NP;
    const idx rows = jet ? 6 * P : P;
    T *dh = sc.dh.data(), *c = sc.c.data(), *dz = sc.dz.data(), *gu = sc.u.data();
    T *gw = sc.v.data();
    // output layer
    const T *HL = ws + lay.H + (s.L - 1) * lay.R + off;
    T w_out[NP] = {};  // this block's share of the output weights' gradient
    for (idx r = 0; r < rows; ++r) {
        T gr;
        bool value = true;
        if (jet) {
            const idx q = r / 6, ch = r % 6;
            gr = g_jet[(ch * s.B + p0 + q) * s.K + k];
            value = ch == 0;
        } else {
            gr = g_val[(p0 + r) * s.K + k];
        }
        if (value) g.b_out += gr;
        for (idx j = 0; j < np; ++j) {
            w_out[j] += HL[r * np + j] * gr;
            dh[r * np + j] = gr * p.w_out[j];
        }
    }
    for (idx j = 0; j < np; ++j) g.w_out[j] += w_out[j];
    if (s.gated) std::fill(gu, gu + rows * np, T(0)), std::fill(gw, gw + rows * np, T(0));
    const T *Wd = ws + lay.W + off;
    auto bias_grad = [&](std::vector<T> &db, const T *d) {
        for (idx r = 0; r < rows; r += jet ? 6 : 1)
            for (idx j = 0; j < np; ++j) db[j] += d[r * np + j];
    };
    for (idx l = s.L - 1; l >= 1; --l) {
        const T *Z = ws + lay.Z + (l - 1) * lay.R + off, *D = ws + lay.D + l * lay.RD + offd;
        const T *Hp = ws + lay.H + (l - 1) * lay.R + off;
        const T *src = dh;
        if (s.gated) {
            const T *Aa = ws + lay.A + (l - 1) * lay.R + off;
            for (idx e = 0; e < rows * np; ++e) gu[e] += dh[e];
            if (jet) {
                gate_jet_back(P, np, dh, Aa, Wd, c, gw);
            } else {
                for (idx e = 0; e < rows * np; ++e) {
                    gw[e] += dh[e] * Aa[e];
                    c[e] = dh[e] * Wd[e];
                }
            }
            src = c;
        }
        if (jet) {
            act_jet_back<T, false>(P, np, src, Z, nullptr, nullptr, D, dz);
        } else {
            for (idx e = 0; e < rows * np; ++e) dz[e] = src[e] * D[e];
        }
        bias_grad(g.b[l - 1], dz);
        outer<T, NP>(rows, s.n, Hp, dz, g.w[l - 1].data());
        matmul<T, NP>(rows, s.n, dz, p.wt[l - 1].data(), dh);
    }
    const T *pts = jet ? x + 2 * p0 : ex + 2 * p0;
    auto input = [&](const T *gin, const std::vector<T> &w, const T *d, std::vector<T> &dw,
                     std::vector<T> &db) {
        if (jet) {
            act_jet_back<T, true>(P, np, gin, nullptr, w.data(), w.data() + np, d, dz);
            for (idx q = 0; q < P; ++q) {
                const T *DZ = dz + 6 * q * np;
                for (idx j = 0; j < np; ++j) {
                    dw[j] += pts[2 * q] * DZ[j] + DZ[np + j];
                    dw[np + j] += pts[2 * q + 1] * DZ[j] + DZ[2 * np + j];
                    db[j] += DZ[j];
                }
            }
        } else {
            for (idx q = 0; q < P; ++q)
                for (idx j = 0; j < np; ++j) {
                    const T e = gin[q * np + j] * d[q * np + j];
                    dw[j] += pts[2 * q] * e;
                    dw[np + j] += pts[2 * q + 1] * e;
                    db[j] += e;
                }
        }
    };
    input(dh, p.w_in, ws + lay.D + offd, g.w_in, g.b_in);
    if (s.gated) {
        for (idx e = 0; e < rows * np; ++e) gu[e] -= gw[e];  // dL/dU = g - dL/d(V - U)
        input(gu, p.w_u, ws + lay.Du + offd, g.w_u, g.b_u);
        input(gw, p.w_v, ws + lay.Dv + offd, g.w_v, g.b_v);
    }
}

// Runs f(k) for the K sub-networks, on up to ``threads`` threads (they are independent).
template <typename F>
void each_network(idx K, int threads, const F &f) {
    if (threads < 2 || K < 2) {
        for (idx k = 0; k < K; ++k) f(k);
        return;
    }
    std::vector<std::thread> helpers;
    for (idx k = 1; k < K; ++k) helpers.emplace_back(f, k);
    f(0);
    for (auto &t : helpers) t.join();
}

// Row offsets of a block in the workspace's R-row and D arrays.
inline idx offset(const Shape &s, bool jet, idx p0, idx np) {
    return (jet ? 6 * p0 : 6 * s.B + p0) * np;
}
inline idx offset_d(const Shape &s, bool jet, idx p0, idx np) {
    return (jet ? 3 * p0 : 3 * s.B + p0) * np;
}

// Layout of one block's own workspace: without a workspace (ws null), forward keeps
// nothing and backward recomputes each block's forward in cache first (for large batches
// the workspace's memory traffic costs more than the recomputation; networks.py).
template <typename T>
Layout block_layout(const Shape &s, idx np) {
    return Layout(Shape{1, s.L, s.n, 0, ROWS, s.gated, 1}, np);
}

template <typename T, int NP, int A>
void forward_net(const Shape &s, const T *const *param, const T *x, const T *ex, T *ws,
                 T *jet_out, T *val_out) {
    const Layout lay = ws ? Layout(s, NP) : block_layout<T>(s, NP);
    each_network(s.K, s.threads, [&](idx k) {
        Scratch<T> sc(NP);
        const Params<T> p = load(s, NP, param, k);
        std::vector<T> own(ws ? 0 : lay.size);
        T *w = ws ? ws + k * lay.size : own.data();
        for (int jet = 1; jet >= 0; --jet)
            for (idx p0 = 0, end = jet ? s.B : s.E; p0 < end; p0 += jet ? POINTS : ROWS)
                forward_block<T, NP, A>(s, lay, p, sc, k, jet, p0,
                                        std::min(jet ? POINTS : ROWS, end - p0), x, ex, w,
                                        ws ? offset(s, jet, p0, NP) : 0,
                                        ws ? offset_d(s, jet, p0, NP) : 0, jet_out, val_out);
    });
}

// Writes sub-network k's gradients g into grad (the parameters' layouts, (K, rows, n)).
template <typename T, int NP>
void store(const Shape &s, const Grads<T> &g, idx k, T *const *grad) {
    const idx n = s.n;
    auto put = [&](T *dst, const std::vector<T> &src, idx rows) {  // padded -> (K, rows, n)
        for (idx i = 0; i < rows; ++i)
            for (idx j = 0; j < n; ++j) dst[(k * rows + i) * n + j] = src[i * NP + j];
    };
    int at = 0;
    put(grad[at++], g.w_in, 2);
    put(grad[at++], g.b_in, 1);
    if (s.gated) {
        put(grad[at++], g.w_u, 2);
        put(grad[at++], g.b_u, 1);
        put(grad[at++], g.w_v, 2);
        put(grad[at++], g.b_v, 1);
    }
    for (idx l = 0; l < s.L - 1; ++l) {
        put(grad[at++], g.w[l], n);
        put(grad[at++], g.b[l], 1);
    }
    for (idx j = 0; j < n; ++j) grad[at][k * n + j] = g.w_out[j];
    grad[at + 1][k] = g.b_out;
}

template <typename T, int NP, int A>
void backward_net(const Shape &s, const T *const *param, const T *x, const T *ex,
                  const T *ws, const T *g_jet, const T *g_val, T *const *grad) {
    const Layout lay = ws ? Layout(s, NP) : block_layout<T>(s, NP);
    each_network(s.K, s.threads, [&](idx k) {
        Scratch<T> sc(NP);
        const Params<T> p = load(s, NP, param, k);
        Grads<T> g(s, NP);
        std::vector<T> own(ws ? 0 : lay.size);
        for (int jet = 1; jet >= 0; --jet) {
            if (!(jet ? g_jet : g_val)) continue;  // null: no gradient reaches these points
            for (idx p0 = 0, end = jet ? s.B : s.E; p0 < end; p0 += jet ? POINTS : ROWS) {
                const idx P = std::min(jet ? POINTS : ROWS, end - p0);
                if (ws) {
                    backward_block<T, NP>(s, lay, p, g, sc, k, jet, p0, P, x, ex,
                                          ws + k * lay.size, offset(s, jet, p0, NP),
                                          offset_d(s, jet, p0, NP), g_jet, g_val);
                } else {
                    forward_block<T, NP, A>(s, lay, p, sc, k, jet, p0, P, x, ex, own.data(), 0,
                                            0, nullptr, nullptr);
                    backward_block<T, NP>(s, lay, p, g, sc, k, jet, p0, P, x, ex, own.data(),
                                          0, 0, g_jet, g_val);
                }
            }
        }
        store<T, NP>(s, g, k, grad);
    });
}

// ---- the paper's loss, fused -----------------------------------------------------------

// The Winslow term (losses.loss_eqns, the paper's residual) at jet points [p0, p0 + P) of
// jet (6, B, 2): returns the sum of |e|^2 there and writes dL/djet of L = mean |e|^2 into g.
// With c = (alpha, -2 beta, gamma), e = c . (r_xixi, r_xieta, r_etaeta) and dL/de = 2 e / B:
// dL/dr_second = c dL/de, and the first derivatives' share comes through alpha = |r_eta|^2,
// beta = r_xi . r_eta, gamma = |r_xi|^2.
template <typename T>
double winslow_block(idx B, idx p0, idx P, const T *jet, T *g) {
    const T scale = T(2) / T(B);
    double sum = 0;
    for (idx q = p0; q < p0 + P; ++q) {
        const T *r[6];
        T *gr[6];
        for (int c = 0; c < 6; ++c) r[c] = jet + (c * B + q) * 2, gr[c] = g + (c * B + q) * 2;
        const T alpha = r[2][0] * r[2][0] + r[2][1] * r[2][1];
        const T beta = r[1][0] * r[2][0] + r[1][1] * r[2][1];
        const T gamma = r[1][0] * r[1][0] + r[1][1] * r[1][1];
        T ge[2], g_alpha = 0, g_beta = 0, g_gamma = 0;  // dL/de; dL/d(alpha, -2 beta, gamma)
        for (int k = 0; k < 2; ++k) {
            const T e = alpha * r[3][k] - 2 * beta * r[4][k] + gamma * r[5][k];
            sum += double(e) * double(e);
            ge[k] = scale * e;
            g_alpha += ge[k] * r[3][k];
            g_beta += ge[k] * r[4][k];
            g_gamma += ge[k] * r[5][k];
        }
        for (int k = 0; k < 2; ++k) {
            gr[0][k] = 0;
            gr[1][k] = 2 * (g_gamma * r[1][k] - g_beta * r[2][k]);
            gr[2][k] = 2 * (g_alpha * r[2][k] - g_beta * r[1][k]);
            gr[3][k] = alpha * ge[k];
            gr[4][k] = -2 * beta * ge[k];
            gr[5][k] = gamma * ge[k];
        }
    }
    return sum;
}

// A point term (losses.loss_points) at value points [p0, p0 + P) of a group of n:
// returns the sum of |v - t|^2 there and writes dL/dv of L = mean |v - t|^2 into g (E, K).
template <typename T>
double points_block(idx K, idx p0, idx P, idx n, const T *val, const T *target, T *g) {
    const T scale = T(2) / T(n);
    double sum = 0;
    for (idx e = p0 * K; e < (p0 + P) * K; ++e) {
        const T d = val[e] - target[e];
        sum += double(d) * double(d);
        g[e] = scale * d;
    }
    return sum;
}

// The paper's loss terms and their gradients in one pass: per block of points, both
// sub-networks' forward, the terms' gradients with respect to their outputs, and backward,
// all in cache (no workspace, no second forward). Term 0 is the Winslow loss at the jet
// points; value points come in G groups (group g ends at ends[g]), each a mean squared
// distance to ``target`` (term 1 + g). Gradients are kept per set: the jet points' in set 0,
// group g's in set sets[g]; grad holds nsets x (parameter count) pointers, set by set.
template <typename T, int NP, int A>
void loss_net(const Shape &s, const T *const *param, const T *x, const T *ex, const T *target,
              idx G, const idx *ends, const int *sets, int nsets, double *terms,
              T *const *grad) {
    const Layout lay = block_layout<T>(s, NP);
    const idx K = s.K;
    Scratch<T> sc(NP);
    std::vector<Params<T>> p;
    std::vector<std::vector<T>> own(K, std::vector<T>(lay.size));
    std::vector<std::vector<Grads<T>>> g(nsets);
    for (idx k = 0; k < K; ++k) {
        p.push_back(load(s, NP, param, k));
        for (auto &set : g) set.emplace_back(s, NP);
    }
    std::vector<T> out(std::max(6 * s.B, s.E) * K), g_out(out.size());
    // one block of P points from p0: forward, output gradient (returns the term's sum), backward
    auto block = [&](bool jet, idx p0, idx P, int set, const auto &output_grad) {
        for (idx k = 0; k < K; ++k)
            forward_block<T, NP, A>(s, lay, p[k], sc, k, jet, p0, P, x, ex, own[k].data(), 0, 0,
                                    out.data(), out.data());
        const double sum = output_grad();
        for (idx k = 0; k < K; ++k)
            backward_block<T, NP>(s, lay, p[k], g[set][k], sc, k, jet, p0, P, x, ex,
                                  own[k].data(), 0, 0, g_out.data(), g_out.data());
        return sum;
    };
    double sum = 0;
    for (idx p0 = 0; p0 < s.B; p0 += POINTS) {
        const idx P = std::min(POINTS, s.B - p0);
        sum += block(true, p0, P, 0,
                     [&] { return winslow_block(s.B, p0, P, out.data(), g_out.data()); });
    }
    terms[0] = s.B ? sum / double(s.B) : 0.0;
    for (idx grp = 0, start = 0; grp < G; start = ends[grp++]) {
        const idx n = ends[grp] - start;
        sum = 0;
        for (idx p0 = start; p0 < ends[grp]; p0 += ROWS) {
            const idx P = std::min(ROWS, ends[grp] - p0);
            sum += block(false, p0, P, sets[grp], [&] {
                return points_block(K, p0, P, n, out.data(), target, g_out.data());
            });
        }
        terms[1 + grp] = n ? sum / double(n) : 0.0;
    }
    const idx count = 2 * (s.gated ? 3 : 1) + 2 * (s.L - 1) + 2;  // parameters per set
    for (int set = 0; set < nsets; ++set)
        for (idx k = 0; k < K; ++k) store<T, NP>(s, g[set][k], k, grad + set * count);
}

// Padded width for n neurons: the smallest of 8, 16, 32, 64 that holds them (0: too many).
inline int padded(idx n) {
    for (int np : {8, 16, 32, 64})
        if (n <= np) return np;
    return 0;
}

// Calls f(width, activation) with the padded width for n and the activation as compile-time
// constants (std::integral_constant); returns 1 when n is too wide for these kernels.
template <typename F>
int dispatch(int act, idx n, const F &f) {
    auto with = [&](auto np) {
        switch (act) {
            case TANH: return f(np, std::integral_constant<int, TANH>{});
            case SIN: return f(np, std::integral_constant<int, SIN>{});
            case SIGMOID: return f(np, std::integral_constant<int, SIGMOID>{});
            default: return f(np, std::integral_constant<int, SWISH>{});
        }
    };
    switch (padded(n)) {
        case 8: with(std::integral_constant<int, 8>{}); return 0;
        case 16: with(std::integral_constant<int, 16>{}); return 0;
        case 32: with(std::integral_constant<int, 32>{}); return 0;
        case 64: with(std::integral_constant<int, 64>{}); return 0;
    }
    return 1;
}

template <typename T>
int forward_any(int act, const Shape &s, const T *const *param, const T *x, const T *ex,
                T *ws, T *jet_out, T *val_out) {
    return dispatch(act, s.n, [&](auto np, auto a) {
        forward_net<T, np, a>(s, param, x, ex, ws, jet_out, val_out);
    });
}

template <typename T>
int backward_any(int act, const Shape &s, const T *const *param, const T *x, const T *ex,
                 const T *ws, const T *g_jet, const T *g_val, T *const *grad) {
    return dispatch(act, s.n, [&](auto np, auto a) {
        backward_net<T, np, a>(s, param, x, ex, ws, g_jet, g_val, grad);
    });
}

template <typename T>
int loss_any(int act, const Shape &s, const T *const *param, const T *x, const T *ex,
             const T *target, idx G, const idx *ends, const int *sets, int nsets,
             double *terms, T *const *grad) {
    if (s.K != 2) return 2;  // the Winslow residual couples exactly two outputs
    for (idx g = 0; g < G; ++g)  // groups in order, within the value points; sets that exist
        if (ends[g] < (g ? ends[g - 1] : 0) || ends[g] > s.E || sets[g] < 1 || sets[g] >= nsets)
            return 3;
    return dispatch(act, s.n, [&](auto np, auto a) {
        loss_net<T, np, a>(s, param, x, ex, target, G, ends, sets, nsets, terms, grad);
    });
}

}  // namespace

extern "C" {

// Elements of workspace per sub-network; -1 when the networks are too wide for these kernels
// (more than 64 neurons: the caller uses torch operations then).
idx net_workspace(idx L, idx n, idx B, idx E, int gated) {
    const int np = padded(n);
    if (np == 0) return -1;
    return Layout(Shape{1, L, n, B, E, gated != 0, 1}, np).size;
}

// Jet (6, B, K) at the B points x (B, 2) and values (E, K) at the E points ex (E, 2);
// ws holds K * net_workspace(...) elements for backward, or is null (backward then
// recomputes). Returns 0 on success.
int net_forward_f32(int act, int gated, int threads, idx K, idx L, idx n, idx B, idx E,
                    const float *const *param, const float *x, const float *ex, float *ws,
                    float *jet_out, float *val_out) {
    return forward_any<float>(act, Shape{K, L, n, B, E, gated != 0, threads}, param, x, ex, ws,
                              jet_out, val_out);
}

int net_forward_f64(int act, int gated, int threads, idx K, idx L, idx n, idx B, idx E,
                    const double *const *param, const double *x, const double *ex, double *ws,
                    double *jet_out, double *val_out) {
    return forward_any<double>(act, Shape{K, L, n, B, E, gated != 0, threads}, param, x, ex, ws,
                               jet_out, val_out);
}

// Gradients (same layouts as the parameters) from dL/djet (6, B, K) and dL/dvalues (E, K);
// a null dL/djet or dL/dvalues stands for zeros (those points are skipped).
int net_backward_f32(int act, int gated, int threads, idx K, idx L, idx n, idx B, idx E,
                     const float *const *param, const float *x, const float *ex,
                     const float *ws, const float *g_jet, const float *g_val,
                     float *const *grad) {
    return backward_any<float>(act, Shape{K, L, n, B, E, gated != 0, threads}, param, x, ex, ws,
                               g_jet, g_val, grad);
}

int net_backward_f64(int act, int gated, int threads, idx K, idx L, idx n, idx B, idx E,
                     const double *const *param, const double *x, const double *ex,
                     const double *ws, const double *g_jet, const double *g_val,
                     double *const *grad) {
    return backward_any<double>(act, Shape{K, L, n, B, E, gated != 0, threads}, param, x, ex,
                                ws, g_jet, g_val, grad);
}

// The paper's loss terms and their gradients (loss_net above) at the B jet points x and the
// E value points ex with targets (E, K): terms holds 1 + G numbers, grad nsets x (parameter
// count) pointers. Returns 0 on success, 1 if the networks are too wide, 2 unless K is 2, 3
// if the groups do not fit the value points or name a set out of 1 .. nsets - 1.
int net_loss_f32(int act, int gated, idx K, idx L, idx n, idx B, idx E,
                 const float *const *param, const float *x, const float *ex,
                 const float *target, idx G, const idx *ends, const int *sets, int nsets,
                 double *terms, float *const *grad) {
    return loss_any<float>(act, Shape{K, L, n, B, E, gated != 0, 1}, param, x, ex, target, G,
                           ends, sets, nsets, terms, grad);
}

int net_loss_f64(int act, int gated, idx K, idx L, idx n, idx B, idx E,
                 const double *const *param, const double *x, const double *ex,
                 const double *target, idx G, const idx *ends, const int *sets, int nsets,
                 double *terms, double *const *grad) {
    return loss_any<double>(act, Shape{K, L, n, B, E, gated != 0, 1}, param, x, ex, target, G,
                            ends, sets, nsets, terms, grad);
}

}  // extern "C"
