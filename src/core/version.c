#include "nbrdf/nbrdf.h"
#include "nbrdf_version.h"

const char *nbrdf_version(void) { return NBRDF_VERSION_STRING; }
