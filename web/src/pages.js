// The router: every page names itself in <body data-page="…"> (server/routes/pages.py) and one module page-*.js
// mounts it (tests/test_web_pages.py); this starts the header, the page, then the page's state from before a
// language switch. The pages carry no inline script, so that the Content-Security-Policy can forbid inline script
// (script-src 'self').

import { mountHeader } from "./header.js";
import { restoreState } from "./state.js";
import { mountAbout } from "./page-about.js";
import { mountAdmin } from "./page-admin.js";
import { mountCourse } from "./page-course.js";
import { mountDrawingPage } from "./page-drawing.js";
import { mountExercise } from "./page-exercise.js";
import { mountExerciseEdit } from "./page-exercise-edit.js";
import { mountExerciseList, mountHome } from "./page-home.js";
import { mountInstructor } from "./page-instructor.js";
import { mountLogin } from "./page-login.js";
import { mountPassword } from "./page-password.js";
import { mountPractice } from "./page-practice.js";
import { mountSignup } from "./page-signup.js";

const byId = (id) => document.getElementById(id);
const segment = (i) => location.pathname.split("/").at(i);  // of the page's address: /exercises/{slug}/edit

const PAGES = {
  about: () => mountAbout(byId("about")),
  admin: () => mountAdmin(byId("admin")),
  course: () => mountCourse(byId("course"), Number(segment(2))),
  drawing: () => mountDrawingPage(byId("drawing-page")),
  exercise: () => mountExercise(byId("exercise"), decodeURIComponent(segment(-1))),
  "exercise-edit": () => mountExerciseEdit(byId("exercise-edit"),
    location.pathname.endsWith("/edit") ? decodeURIComponent(segment(2)) : null),
  exercises: () => Promise.all([mountHome(byId("home")), mountExerciseList(byId("list"))]),
  instructor: () => mountInstructor(byId("submissions")),
  login: () => mountLogin(byId("login"), byId("message")),
  password: () => mountPassword(byId("password-form")),
  practice: () => mountPractice(byId("practice")),
  signup: () => mountSignup(byId("signup-form")),
};

export async function boot() {
  mountHeader();
  await PAGES[document.body.dataset.page]?.();
  restoreState();  // after a language switch: the program and the 3D view as they were
}
