// The bundle's entry: everything the pages call, as window.PalTrainer.
import { mountEditor } from "./main.js";
import { mountExercise, mountExerciseList, mountInstructor, mountLogin, mountViz } from "./pages.js";

window.PalTrainer = { mountEditor, mountExercise, mountExerciseList, mountInstructor, mountLogin, mountViz };
