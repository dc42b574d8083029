/* The part of IPOPT that ipopt-sys binds: its plain C interface, and the run-time loader of the
   Pardiso linear solver through which codesign plugs in its own sparse LDL^T. */
#include <IpStdCInterface.h>
#include <PardisoLoader.h>
