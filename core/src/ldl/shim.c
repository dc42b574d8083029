/* The ABI of IPOPT's run-time Pardiso loader, forwarded to codesign's Rust LDL^T (src/ldl/pardiso.rs).
 *
 * Built by build.rs into a shared object whose SONAME is libpardiso.so, embedded in the codesign
 * binary and loaded from an anonymous file before IPOPT's first solve (src/ldl/loader.rs). IPOPT
 * finds `pardisoinit` and `pardiso` here with dlsym; `pardiso_ipopt_newinterface` only marks the
 * Pardiso 4 calling convention. Until codesign_ldl_bind has been called every call fails with
 * error -1, so a stray load can never reach a null function. */

typedef void (*codesign_init_fn)(void **pt, const int *mtype, const int *solver, int *iparm,
                                 double *dparm, int *error);
typedef void (*codesign_solve_fn)(void **pt, const int *maxfct, const int *mnum, const int *mtype,
                                  const int *phase, const int *n, const double *a, const int *ia,
                                  const int *ja, const int *perm, const int *nrhs, int *iparm,
                                  const int *msglvl, double *b, double *x, int *error,
                                  double *dparm);

static codesign_init_fn bound_init;
static codesign_solve_fn bound_solve;

void codesign_ldl_bind(codesign_init_fn init, codesign_solve_fn solve) {
  bound_init = init;
  bound_solve = solve;
}

void pardiso_ipopt_newinterface(void) {}

void pardisoinit(void **pt, const int *mtype, const int *solver, int *iparm, double *dparm,
                 int *error) {
  if (bound_init == 0) {
    *error = -1;
    return;
  }
  bound_init(pt, mtype, solver, iparm, dparm, error);
}

void pardiso(void **pt, const int *maxfct, const int *mnum, const int *mtype, const int *phase,
             const int *n, const double *a, const int *ia, const int *ja, const int *perm,
             const int *nrhs, int *iparm, const int *msglvl, double *b, double *x, int *error,
             double *dparm) {
  if (bound_solve == 0) {
    *error = -1;
    return;
  }
  bound_solve(pt, maxfct, mnum, mtype, phase, n, a, ia, ja, perm, nrhs, iparm, msglvl, b, x,
              error, dparm);
}
