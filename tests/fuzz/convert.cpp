// Fuzz target: the whole convert pipeline on the Andres 2011 cell: CL text -> ClReader ->
// PostSession (tracking, KRL through the krc4_lin templates, a joints CSV) -> finished program
// in a scratch directory, split every 20 motions.
#include <sstream>

#include "fuzz_support.hpp"
#include "redpost/cl/reader.hpp"
#include "redpost/kinematics/cell_xml.hpp"
#include "redpost/krl/template.hpp"
#include "redpost/post/session.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const redpost::Cell cell = redpost::load_cell(
      redpost::fuzz::source_path("definitions/cells/andres2011_kr15_track_table.xml"));
  static const redpost::KrlTemplateSet templates =
      redpost::load_krl_templates(redpost::fuzz::source_path("definitions/krl/krc4_lin.xml"));
  const std::filesystem::path dir = redpost::fuzz::fresh_scratch_dir();
  return redpost::fuzz::run_one([&] {
    std::istringstream in(redpost::fuzz::as_text(data, size));
    redpost::PostOptions options;
    options.program.name = "FUZZ";
    options.program.output_dir = dir.string();
    options.program.motions_per_file = 20;
    options.source_name = "fuzz.apt";
    options.joints_csv_path = (dir / "joints.csv").string();
    redpost::ClReader reader(in, options.source_name);
    redpost::PostSession session(cell, templates, options);
    redpost::ClEvent event;
    while (reader.next(event))
      session.handle(event);
    session.finish();
  });
}
