// The parameter window's Task page: the tooth and task pickers, the task's title and instructions, and teacher mode's Record as ideal.
#pragma once

#include "ui/panel_widgets.h"

namespace dentsim::ui::panel {

// Draws the page: picking raises tooth_changed or task_changed with the choice in the state, a
// task file that does not load shows its error and raises nothing, and Record as ideal (teacher
// mode) is offered only for a task file whose segment is being recorded, with a tooltip saying why
// not otherwise.
void taskPage(const Frame& f);

}  // namespace dentsim::ui::panel
