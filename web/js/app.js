// The caretakers' UI: who is logged in decides between the login form and the app; the part of
// the URL after '#' decides the page. Each page renders into <main> and may return a function
// that stops what it started (live updates) when the caretaker leaves it.

import { h, replace } from './dom.js';
import { closeFeed } from './events.js';
import * as session from './session.js';
import { renderLogin } from './pages/login.js';
import * as account from './pages/account.js';
import * as admin from './pages/admin.js';
import * as register from './pages/register.js';
import * as robots from './pages/robots.js';
import * as tag from './pages/tag.js';
import * as tags from './pages/tags.js';
import * as tasks from './pages/tasks.js';

const app = document.getElementById('app');

/** Route patterns on the hash, first match wins; groups are URL-decoded into `params`. */
const ROUTES = [
  { pattern: /^#\/tags\/([^/?]+)\/edit$/, page: tag.renderEdit, nav: 'tags' },
  { pattern: /^#\/tags\/([^/?]+)$/, page: tag.render, nav: 'tags' },
  { pattern: /^#\/register(?:\?epc=([^&]*))?$/, page: register.render, nav: 'register' },
  { pattern: /^#\/tasks$/, page: tasks.render, nav: 'tasks' },
  { pattern: /^#\/robots$/, page: robots.render, nav: 'robots' },
  { pattern: /^#\/admin$/, page: admin.render, nav: 'admin', adminOnly: true },
  { pattern: /^#\/account$/, page: account.render, nav: 'account' },
  { pattern: /^(#\/tags)?(\?.*)?$|^#?\/?$/, page: tags.render, nav: 'tags' },
];

const NAV = [
  ['tags', '#/tags', 'Tags'],
  ['register', '#/register', 'Register a tag'],
  ['tasks', '#/tasks', 'Tasks'],
  ['robots', '#/robots', 'Robots'],
  ['admin', '#/admin', 'Admin', true],
];

let stopPage = null;
let shell = null;

function buildShell() {
  const user = session.user();
  const links = NAV.filter(([, , , adminOnly]) => !adminOnly || session.isAdmin())
    .map(([key, href, label]) => h('a', { href, dataset: { nav: key } }, label));
  const logout = h('button', { type: 'button', class: 'link', on: { click: logOut } }, 'Log out');
  const main = h('main', { id: 'main', class: 'page', tabindex: '-1' });
  replace(app,
    h('header', { class: 'topbar' },
      h('a', { class: 'brand', href: '#/tags' }, h('span', { class: 'brand-mark', 'aria-hidden': 'true' }), 'PPS-tag registry'),
      h('nav', { class: 'mainnav', 'aria-label': 'Main' }, links),
      h('div', { class: 'who' },
        h('a', { href: '#/account', dataset: { nav: 'account' }, title: 'Your account' }, `${user.name} (${user.role})`),
        logout)),
    main);
  return { main, links: app.querySelectorAll('[data-nav]') };
}

async function route() {
  if (!session.user()) return;
  stopPage?.();
  stopPage = null;
  shell ??= buildShell();
  const hash = location.hash || '#/tags';
  const match = ROUTES.map((r) => ({ r, m: hash.match(r.pattern) })).find(({ m }) => m);
  const { main } = shell;
  for (const link of shell.links) {
    if (link.dataset.nav === match?.r.nav) link.setAttribute('aria-current', 'page');
    else link.removeAttribute('aria-current');
  }
  replace(main);
  if (!match || (match.r.adminOnly && !session.isAdmin())) {
    replace(main, h('h1', {}, 'Not found'), h('p', {}, 'There is no such page. ', h('a', { href: '#/tags' }, 'Go to the tags.')));
    return;
  }
  const params = match.m.slice(1).map((part) => (part === undefined ? undefined : decodeURIComponent(part)));
  try {
    const stop = await match.r.page(main, params);
    if (typeof stop === 'function') stopPage = stop;
  } catch (error) {
    if (error.status === 401) return;
    replace(main, h('h1', {}, 'Something went wrong'), h('p', { class: 'status bad', role: 'alert' }, error.message),
      h('p', {}, h('a', { href: '#/tags' }, 'Back to the tags')));
  }
  if (document.activeElement === document.body || !main.contains(document.activeElement)) {
    (main.querySelector('h1') ?? main).setAttribute('tabindex', '-1');
    (main.querySelector('h1') ?? main).focus({ preventScroll: true });
  }
}

function showLogin(message) {
  stopPage?.();
  stopPage = null;
  shell = null;
  closeFeed();
  document.title = 'Log in · PPS-tag registry';
  renderLogin(app, { message, onLoggedIn: () => route() });
}

async function logOut() {
  await session.logout().catch(() => {});
  showLogin('You are logged out.');
}

window.addEventListener('hashchange', route);
window.addEventListener('pps:session-ended', () => {
  if (session.user()) {
    session.forget();
    showLogin('Your session has ended. Log in again to go on.');
  }
});

async function start() {
  try {
    const user = await session.load();
    if (user) route();
    else showLogin();
  } catch (error) {
    replace(app, h('main', { class: 'page' }, h('h1', {}, 'PPS-tag registry'),
      h('p', { class: 'status bad', role: 'alert' }, `The registry cannot be reached: ${error.message}`)));
  }
}

start();
