// The bundle's entry: everything the pages call, as window.PalTrainer.
import { installBearer } from "./lti.js";  // first: storage fallback before any module reads it
import { instructorCourseLinks, keepFrameOnLinks } from "./lti-frame.js";
import { mountEditor, setTools } from "./main.js";
import {
  mountExercise, mountExerciseList, mountInstructor, mountLogin, mountPracticeSetup, mountViz,
} from "./pages.js";

import { boot } from "./boot.js";
import { translatePage } from "./i18n.js";
import { safeNext } from "./redirect.js";

installBearer();  // before anything asks the API (LTI launches: no cookie in the iframe)
translatePage();
window.PalTrainer = {
  mountEditor, mountExercise, mountExerciseList, mountInstructor, mountLogin, mountPracticeSetup, mountViz, safeNext,
  setTools,
};
boot();
keepFrameOnLinks();  // in a platform's frame: links keep the platform and the token
instructorCourseLinks();  // and an instructor finds their course page there
