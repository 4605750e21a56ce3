/* A C99 host of libredpost: replays a CL file through the C ABI (reader + session), as any host
 * in another language would (docs/c-abi.md).
 *
 * Usage: c_host CL_FILE CELL_XML OUTPUT_DIR PROGRAM_NAME [KRL_TEMPLATES]
 * e.g.   c_host examples/cl/pocket_arcs.apt definitions/cells/andres2011_kr15_track_table.xml \
 *               /tmp/out POCKET_ARCS
 * writes the same bytes as `redpost convert ... --name POCKET_ARCS`. Exit 0 on success, 2 on an
 * error (with "c_host: message" on stderr). */
#include <stdio.h>

#include "redpost.h"

static int fail(const char* message) {
  fprintf(stderr, "c_host: %s\n", message);
  return 2;
}

int main(int argc, char** argv) {
  rp_options options;
  rp_session* session = NULL;
  rp_reader* reader = NULL;
  rp_event event;
  rp_summary summary;
  int more = 1;
  int i;
  const char* path;

  if (argc != 5 && argc != 6) {
    fprintf(stderr, "usage: %s CL_FILE CELL_XML OUTPUT_DIR PROGRAM_NAME [KRL_TEMPLATES]\n",
            argv[0]);
    return 2;
  }

  /* Defaults first, then what this host knows. */
  rp_options_init(&options);
  options.cell_path = argv[2];
  options.output_dir = argv[3];
  options.program_name = argv[4];
  options.krl_path = argc == 6 ? argv[5] : NULL; /* NULL: the shipped krc4_lin */
  options.source_name = argv[1];                 /* messages name the CL file */

  if (rp_open(&options, &session) != RP_OK)
    return fail(rp_last_error(NULL)); /* session is NULL: the message is per thread */
  if (rp_reader_open(argv[1], options.chordal_tolerance_mm, &reader) != RP_OK) {
    rp_free(session);
    return fail(rp_last_error(NULL));
  }

  /* Every event of the file, in order; the reader's line goes with each event. */
  for (;;) {
    if (rp_reader_next(reader, &event, &more) != RP_OK) {
      fail(rp_reader_last_error(reader));
      rp_reader_free(reader);
      rp_free(session); /* an unclosed session writes nothing */
      return 2;
    }
    if (!more)
      break;
    if (rp_session_event(session, &event) != RP_OK) {
      fail(rp_last_error(session));
      rp_reader_free(reader);
      rp_free(session);
      return 2;
    }
  }
  for (i = 0; rp_reader_warning(reader, i) != NULL; ++i)
    fprintf(stderr, "warning: %s\n", rp_reader_warning(reader, i));
  rp_reader_free(reader);

  if (rp_close(session) != RP_OK) {
    fail(rp_last_error(session));
    rp_free(session);
    return 2;
  }
  rp_summary_get(session, &summary);
  printf("poses %ld, motions %ld, lowest 1/kappa_F %.3f (CL line %d)\n", summary.poses,
         summary.motions, summary.lowest_inv_condition, summary.lowest_inv_condition_line);
  for (i = 0; rp_warning(session, i) != NULL; ++i)
    fprintf(stderr, "warning: %s\n", rp_warning(session, i));
  for (i = 0; (path = rp_output_file(session, i)) != NULL; ++i)
    printf("wrote %s\n", path);
  rp_free(session);
  return 0;
}
