// The bundle's entry: it starts the page (pages.js) and offers the mount functions as window.PalTrainer.
import { installBearer } from "./lti.js";  // first: storage fallback before any module reads it
import { instructorCourseLinks, keepFrameOnLinks } from "./lti-frame.js";
import { mountEditor, setTools } from "./main.js";
import { mountExercise } from "./page-exercise.js";
import { mountExerciseList } from "./page-home.js";
import { mountInstructor } from "./page-instructor.js";
import { mountLogin } from "./page-login.js";
import { mountPracticeSetup } from "./page-practice.js";
import { boot } from "./pages.js";
import { mountViz } from "./viz.js";

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
