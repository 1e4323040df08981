// Starts the page: every page names itself in <body data-page="…"> and this mounts it. The pages carry no
// inline script, so that the Content-Security-Policy can forbid inline script (script-src 'self').

import { mountAbout } from "./about.js";
import { mountAdmin } from "./page-admin.js";
import { mountDrawingPage } from "./drawing-viewer.js";
import { mountCourse } from "./page-course.js";
import { mountExerciseEdit } from "./page-exercise-edit.js";
import { mountPassword, mountSignup } from "./page-account.js";
import { mountHeader } from "./header.js";
import { mountHome } from "./page-home.js";
import { practiceBlocked } from "./page-exam.js";
import { mountPractice } from "./page-practice.js";
import { restoreState } from "./state.js";
import { mountExercise, mountExerciseList, mountInstructor, mountLogin } from "./pages.js";

const PAGES = {
  practice: async () => (await practiceBlocked(document.getElementById("practice")))
    || mountPractice(document.getElementById("practice")),
  exercise: () => mountExercise(document.getElementById("exercise"),
    decodeURIComponent(location.pathname.split("/").pop())),
  "exercise-edit": () => mountExerciseEdit(document.getElementById("exercise-edit"),
    location.pathname.endsWith("/edit") ? decodeURIComponent(location.pathname.split("/")[2]) : null),
  exercises: () => Promise.all([mountHome(document.getElementById("home")), mountExerciseList(document.getElementById("list"))]),
  instructor: () => mountInstructor(document.getElementById("submissions")),
  login: () => mountLogin(document.getElementById("login"), document.getElementById("message")),
  about: () => mountAbout(document.getElementById("about")),
  password: () => mountPassword(document.getElementById("password-form")),
  signup: () => mountSignup(document.getElementById("signup-form")),
  drawing: () => mountDrawingPage(document.getElementById("drawing-page")),
  admin: () => mountAdmin(document.getElementById("admin")),
  course: () => mountCourse(document.getElementById("course"), Number(location.pathname.split("/")[2])),
};

export async function boot() {
  mountHeader();
  await PAGES[document.body.dataset.page]?.();
  restoreState();  // after a language switch: the program and the 3D view as they were
}
