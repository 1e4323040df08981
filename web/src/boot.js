// Starts the page: every page names itself in <body data-page="…"> and this mounts it. The pages carry no
// inline script, so that the Content-Security-Policy can forbid inline script (script-src 'self').

import { mountPractice } from "./page-practice.js";
import { mountExercise, mountExerciseList, mountInstructor, mountLogin } from "./pages.js";

const PAGES = {
  practice: () => mountPractice(document.getElementById("practice")),
  exercise: () => mountExercise(document.getElementById("exercise"),
    decodeURIComponent(location.pathname.split("/").pop())),
  exercises: () => mountExerciseList(document.getElementById("list")),
  instructor: () => mountInstructor(document.getElementById("submissions")),
  login: () => mountLogin(document.getElementById("login"), document.getElementById("message")),
};

export function boot() {
  return PAGES[document.body.dataset.page]?.();
}
