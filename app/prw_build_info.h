/* prw_build_info — what the binary was built from (for figures and file metadata). */
#ifndef PRW_BUILD_INFO_H
#define PRW_BUILD_INFO_H

/* Short git hash of the source tree at BUILD time ("-dirty" with uncommitted changes to tracked
 * files; "unknown" outside a git checkout). */
const char *prw_build_git_hash(void);

#endif
