// Fused CPU kernels for one jet layer of the coordinate networks (see networks.py).
//
// A layer's rows (networks.py, "row layout"): per sub-network, the five derivative channels
// d_xi, d_eta, d_xixi, d_xieta, d_etaeta of the B jet points (S = B * neurons elements each),
// then the values of the jet points and of value-only points (St >= S elements). Arrays are
// contiguous (k, 5 S + St); p and q are (k, St); d, keeping sigma', sigma'', sigma''', is
// (k, St + 2 S). One pass over the elements replaces the ~40 (forward) and ~80 (backward)
// small tensor operations of the same chain and Leibniz rules written with torch operations.
//
// Built by native.py with the system C++ compiler; no Python or torch headers needed.

#include <cstddef>

namespace {

using idx = std::ptrdiff_t;

enum Activation { TANH = 0, SIN = 1, SIGMOID = 2, SWISH = 3 };

// sigma(z) and its first three derivatives, from z and p (tanh(z), sin(z) or sigmoid(z),
// computed by torch's vectorised functions) and q (cos(z), sine only).
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

// a = jet of sigma(z) (chain rule); with GATED also h = u + a * w (Leibniz rule: the
// shortcut network's U + Z (V - U) on jets, w = V - U).
template <typename T, int A, bool GATED>
void forward(idx k, idx S, idx St, const T *__restrict z, const T *__restrict p,
             const T *__restrict q, const T *__restrict u, const T *__restrict w,
             T *__restrict a, T *__restrict h, T *__restrict d) {
    const idx R = 5 * S + St;
    for (idx b = 0; b < k; ++b) {
        const T *Z = z + R * b, *Zv = Z + 5 * S, *P = p + St * b;
        const T *Q = q ? q + St * b : P;
        T *Ao = a + R * b, *Av = Ao + 5 * S, *D = d + (St + 2 * S) * b;
        const T *U = GATED ? u + R * b : nullptr, *W = GATED ? w + R * b : nullptr;
        const T *Uv = GATED ? U + 5 * S : nullptr, *Wv = GATED ? W + 5 * S : nullptr;
        T *H = GATED ? h + R * b : nullptr, *Hv = GATED ? H + 5 * S : nullptr;
#pragma GCC ivdep
        for (idx e = 0; e < S; ++e) {
            T s, d1, d2, d3;
            derivatives<T, A>(Zv[e], P[e], Q[e], s, d1, d2, d3);
            const T z1 = Z[e], z2 = Z[S + e];
            const T a0 = s, a1 = d1 * z1, a2 = d1 * z2;
            const T a3 = d2 * z1 * z1 + d1 * Z[2 * S + e];
            const T a4 = d2 * z1 * z2 + d1 * Z[3 * S + e];
            const T a5 = d2 * z2 * z2 + d1 * Z[4 * S + e];
            Av[e] = a0; Ao[e] = a1; Ao[S + e] = a2;
            Ao[2 * S + e] = a3; Ao[3 * S + e] = a4; Ao[4 * S + e] = a5;
            D[e] = d1; D[St + e] = d2; D[St + S + e] = d3;
            if (GATED) {
                const T w0 = Wv[e], w1 = W[e], w2 = W[S + e];
                Hv[e] = Uv[e] + a0 * w0;
                H[e] = U[e] + a1 * w0 + a0 * w1;
                H[S + e] = U[S + e] + a2 * w0 + a0 * w2;
                H[2 * S + e] = U[2 * S + e] + a3 * w0 + 2 * a1 * w1 + a0 * W[2 * S + e];
                H[3 * S + e] = U[3 * S + e] + a4 * w0 + a1 * w2 + a2 * w1 + a0 * W[3 * S + e];
                H[4 * S + e] = U[4 * S + e] + a5 * w0 + 2 * a2 * w2 + a0 * W[4 * S + e];
            }
        }
#pragma GCC ivdep
        for (idx e = S; e < St; ++e) {  // value-only points
            T s, d1, d2, d3;
            derivatives<T, A>(Zv[e], P[e], Q[e], s, d1, d2, d3);
            Av[e] = s;
            D[e] = d1;
            if (GATED) Hv[e] = Uv[e] + s * Wv[e];
        }
    }
}

// Reverse of forward: from g = dL/dh (GATED) or dL/da, gives dz = dL/dz and, when GATED,
// adds dL/du to gu and dL/dw to gw.
template <typename T, bool GATED>
void backward(idx k, idx S, idx St, const T *__restrict g, const T *__restrict z,
              const T *__restrict d, const T *__restrict a, const T *__restrict w,
              T *__restrict gu, T *__restrict gw, T *__restrict dz) {
    const idx R = 5 * S + St;
    for (idx b = 0; b < k; ++b) {
        const T *G = g + R * b, *Gv = G + 5 * S, *Z = z + R * b, *D = d + (St + 2 * S) * b;
        const T *Ai = GATED ? a + R * b : nullptr, *W = GATED ? w + R * b : nullptr;
        const T *Av = GATED ? Ai + 5 * S : nullptr, *Wv = GATED ? W + 5 * S : nullptr;
        T *GU = GATED ? gu + R * b : nullptr, *GW = GATED ? gw + R * b : nullptr;
        T *GUv = GATED ? GU + 5 * S : nullptr, *GWv = GATED ? GW + 5 * S : nullptr;
        T *DZ = dz + R * b, *DZv = DZ + 5 * S;
#pragma GCC ivdep
        for (idx e = 0; e < S; ++e) {
            const T g0 = Gv[e], g1 = G[e], g2 = G[S + e];
            const T g3 = G[2 * S + e], g4 = G[3 * S + e], g5 = G[4 * S + e];
            T c0 = g0, c1 = g1, c2 = g2, c3 = g3, c4 = g4, c5 = g5;  // dL/da
            if (GATED) {
                const T w0 = Wv[e], w1 = W[e], w2 = W[S + e];
                const T a0 = Av[e], a1 = Ai[e], a2 = Ai[S + e];
                GUv[e] += g0; GU[e] += g1; GU[S + e] += g2;
                GU[2 * S + e] += g3; GU[3 * S + e] += g4; GU[4 * S + e] += g5;
                c0 = g0 * w0 + g1 * w1 + g2 * w2 + g3 * W[2 * S + e] + g4 * W[3 * S + e]
                     + g5 * W[4 * S + e];
                c1 = g1 * w0 + 2 * g3 * w1 + g4 * w2;
                c2 = g2 * w0 + g4 * w1 + 2 * g5 * w2;
                c3 = g3 * w0; c4 = g4 * w0; c5 = g5 * w0;
                GWv[e] += g0 * a0 + g1 * a1 + g2 * a2 + g3 * Ai[2 * S + e]
                          + g4 * Ai[3 * S + e] + g5 * Ai[4 * S + e];
                GW[e] += g1 * a0 + 2 * g3 * a1 + g4 * a2;
                GW[S + e] += g2 * a0 + g4 * a1 + 2 * g5 * a2;
                GW[2 * S + e] += g3 * a0; GW[3 * S + e] += g4 * a0; GW[4 * S + e] += g5 * a0;
            }
            const T d1 = D[e], d2 = D[St + e], d3 = D[St + S + e];
            const T z1 = Z[e], z2 = Z[S + e];
            const T gd1 = c1 * z1 + c2 * z2 + c3 * Z[2 * S + e] + c4 * Z[3 * S + e]
                          + c5 * Z[4 * S + e];
            const T gd2 = (c3 * z1 + c4 * z2) * z1 + c5 * z2 * z2;
            DZv[e] = c0 * d1 + gd1 * d2 + gd2 * d3;
            DZ[e] = c1 * d1 + d2 * (2 * c3 * z1 + c4 * z2);
            DZ[S + e] = c2 * d1 + d2 * (c4 * z1 + 2 * c5 * z2);
            DZ[2 * S + e] = c3 * d1; DZ[3 * S + e] = c4 * d1; DZ[4 * S + e] = c5 * d1;
        }
#pragma GCC ivdep
        for (idx e = S; e < St; ++e) {  // value-only points
            T c0 = Gv[e];
            if (GATED) {
                GUv[e] += c0;
                GWv[e] += c0 * Av[e];
                c0 *= Wv[e];
            }
            DZv[e] = c0 * D[e];
        }
    }
}

template <typename T>
void forward_any(int act, idx k, idx S, idx St, const T *z, const T *p, const T *q,
                 const T *u, const T *w, T *a, T *h, T *d) {
    const bool gated = u != nullptr;
#define PINN_CASE(A)                                                                   \
    case A:                                                                            \
        return gated ? forward<T, A, true>(k, S, St, z, p, q, u, w, a, h, d)           \
                     : forward<T, A, false>(k, S, St, z, p, q, u, w, a, h, d);
    switch (act) {
        PINN_CASE(TANH)
        PINN_CASE(SIN)
        PINN_CASE(SIGMOID)
        PINN_CASE(SWISH)
    }
#undef PINN_CASE
}

template <typename T>
void backward_any(idx k, idx S, idx St, const T *g, const T *z, const T *d, const T *a,
                  const T *w, T *gu, T *gw, T *dz) {
    if (a != nullptr)
        backward<T, true>(k, S, St, g, z, d, a, w, gu, gw, dz);
    else
        backward<T, false>(k, S, St, g, z, d, a, w, gu, gw, dz);
}

}  // namespace

extern "C" {

void jet_forward_f32(int act, idx k, idx S, idx St, const float *z, const float *p,
                     const float *q, const float *u, const float *w, float *a, float *h,
                     float *d) {
    forward_any<float>(act, k, S, St, z, p, q, u, w, a, h, d);
}

void jet_forward_f64(int act, idx k, idx S, idx St, const double *z, const double *p,
                     const double *q, const double *u, const double *w, double *a, double *h,
                     double *d) {
    forward_any<double>(act, k, S, St, z, p, q, u, w, a, h, d);
}

void jet_backward_f32(idx k, idx S, idx St, const float *g, const float *z, const float *d,
                      const float *a, const float *w, float *gu, float *gw, float *dz) {
    backward_any<float>(k, S, St, g, z, d, a, w, gu, gw, dz);
}

void jet_backward_f64(idx k, idx S, idx St, const double *g, const double *z,
                      const double *d, const double *a, const double *w, double *gu,
                      double *gw, double *dz) {
    backward_any<double>(k, S, St, g, z, d, a, w, gu, gw, dz);
}

}  // extern "C"
