// The bundle's entry: everything the pages call, as window.PalTrainer.
import { mountEditor, setTools } from "./main.js";
import {
  mountExercise, mountExerciseList, mountInstructor, mountLogin, mountPracticeSetup, mountViz,
} from "./pages.js";

import { translatePage } from "./i18n.js";

translatePage();
window.PalTrainer = {
  mountEditor, mountExercise, mountExerciseList, mountInstructor, mountLogin, mountPracticeSetup, mountViz, setTools,
};
