// The lowest contract: every layer sees it.
#define FIXTURE_COMPAT 1
