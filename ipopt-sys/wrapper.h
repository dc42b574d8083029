/* The part of IPOPT that ipopt-sys binds: its plain C interface. */
#include <IpStdCInterface.h>
