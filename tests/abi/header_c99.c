/* redpost.h compiles as strict C99 (-std=c99 -Wall -Wextra -pedantic -Werror) and links: every
 * type and a few functions used from C, without touching a file. */
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "redpost.h"

int main(void) {
  rp_options options;
  rp_session* session = NULL;
  rp_move_info move;
  rp_summary summary;
  rp_joint_range_info range;
  rp_event event;
  rp_reader* reader = NULL;
  int more = 0;

  rp_options_init(&options);
  if (options.struct_size != sizeof options || options.apo_mm != 0.5 ||
      options.cl_line_every != 50 || options.chordal_tolerance_mm != 0.01) {
    fprintf(stderr, "rp_options_init: wrong defaults\n");
    return 1;
  }
  if (strcmp(rp_version(), REDPOST_VERSION) != 0) {
    fprintf(stderr, "rp_version %s != %s\n", rp_version(), REDPOST_VERSION);
    return 1;
  }
  /* NULL handles: statuses, never a crash. */
  memset(&event, 0, sizeof event);
  if (rp_linear_move(session, 0, 0, 0, 0, 0, 1) != RP_ERR_NULL ||
      rp_last_move(session, &move) != RP_ERR_NULL ||
      rp_summary_get(session, &summary) != RP_ERR_NULL ||
      rp_joint_range(session, 0, &range) != RP_ERR_NULL ||
      rp_session_event(session, &event) != RP_ERR_NULL ||
      rp_reader_next(reader, &event, &more) != RP_ERR_NULL) {
    fprintf(stderr, "a NULL handle was not RP_ERR_NULL\n");
    return 1;
  }
  rp_free(session);
  rp_reader_free(reader);
  printf("redpost %s from C99: ok\n", rp_version());
  return 0;
}
