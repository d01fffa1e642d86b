// Contact of membranes with each other (two sets) and with themselves (`self`): the nodes of
// each set against the faces of the other (or its own faces away from the node), node to face
// with a penalty on both sides of each face (docs/contact.md, "Sheets").
#pragma once

#include <memory>

#include "velum/load/contact_load.hpp"

namespace velum {

std::unique_ptr<Load> make_sheet_contact(ContactLoad p);

}  // namespace velum
