#pragma once
// Every picture of a run by name, from a RunSnapshot: the run's plots (report_plots.h) and a pair's episode —
// its current θ on its own course, as the run's walker settings play it — as a whole-course picture, a
// filmstrip or an animated GIF. One code path for `poetctl picture` on a run directory and for the status
// socket's /pictures/ endpoints on a live run.
//
//   scores, levels, annecs, tree, rose            the run            .png or .svg
//   course, filmstrip (with a pair id)            a pair's episode   .png or .svg
//   walk (with a pair id)                         a pair's episode   .gif
//   lineage (with a pair id)                      the courses of the pair's line of ancestors, first environment
//                                                 first, one above another (course_stack.h)   .png or .svg

#include <string>

#include "common/plumbing/expected.h"
#include "report/picture_request.h"
#include "run_directory/reading/run_snapshot.h"

namespace poet {

// The picture's bytes, or an error naming what is wrong (unknown pair, a kind in an encoding it has not).
Expected<std::string> render_run_picture(const RunSnapshot& run, const PictureRequest& request);

}  // namespace poet
