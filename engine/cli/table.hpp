// The CLI's names for the terminal table and its number formats (engine/report/text_table.hpp).
#pragma once

#include "engine/report/text_table.hpp"

namespace trackassoc::cli {

using report::fmt;
using report::percent;
using report::TextTable;

}  // namespace trackassoc::cli
