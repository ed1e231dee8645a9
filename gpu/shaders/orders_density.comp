// J_k at a texel (radius i, sun k, view j, azimuth a): the sphere rule's sum of the
// phase matrices' rows times I_{k-1} (orders_incoming.comp), times the scattering
// coefficients at the radius; stored as its logarithm.
void main() {
  int nout = params.nmu * params.na, nq = params.nz * params.nphi, e = orders_item();
  if (e >= params.n_items) return;
  int i = e / (params.ns * nout), k = (e / nout) % params.ns, o = e % nout;
  float jr[ATMOSH_ORDERS_MAX_WAVELENGTHS], jm[ATMOSH_ORDERS_MAX_WAVELENGTHS];
  for (int w = 0; w < params.nw; ++w) jr[w] = jm[w] = 0.0;
  int in0 = (i * params.ns + k) * nq * params.nw, row = (i * nout + o) * nq;
  for (int q = 0; q < nq; ++q) {
    float a = phase_r[row + q], b = phase_m[row + q];
    for (int w = 0; w < params.nw; ++w) {
      jr[w] += a * incoming[in0 + q * params.nw + w];
      jm[w] += b * incoming[in0 + q * params.nw + w];
    }
  }
  int dst = orders_texel(i, o / params.na, k, o % params.na, params.nmu, params.ns, params.na) * params.nw;
  for (int w = 0; w < params.nw; ++w)
    tab_out[dst + w] = orders_log(float(geom[params.off_sr + w] * geom[params.off_rho_r + i] * double(jr[w]) +
                                        geom[params.off_sm + w] * geom[params.off_rho_m + i] * double(jm[w])));
}
