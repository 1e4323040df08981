// Dynamic registration done: tell the platform's registration dialog to close (LTI Dynamic Registration 1.0).
(window.opener || window.parent).postMessage({ subject: "org.imsglobal.lti.close" }, "*");
