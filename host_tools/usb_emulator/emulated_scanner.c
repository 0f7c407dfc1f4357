/*
 * Emulated pitvol USB scanner on umockdev (see emulated_scanner.h).
 *
 * How URBs are served. umockdev's preload library forwards every ioctl on
 * the emulated /dev/bus/usb/001/NNN to the "handle-ioctl" signal of our
 * UMockdevIoctlBase, which runs on the test bed's worker thread while the
 * calling (libusb) thread waits. Client memory is reached through
 * UMockdevIoctlData: resolve() copies a pointed-to block in, and whatever
 * we change is written back when the ioctl completes.
 *   SUBMITURB   the URB and its buffer are resolved and queued (a control
 *               URB is executed at once: START/STOP, and queued as done);
 *   REAPURBNDELAY  the oldest queued URB of that client that can complete
 *               now is completed: bulk data is assigned AT REAP TIME from
 *               the stream position, so the order the host reaps in is the
 *               byte order; status/actual_length are set, and the reap
 *               argument is pointed at the URB (set_ptr). Nothing ready:
 *               -EAGAIN (libusb polls the node, which is always ready
 *               under umockdev, so it simply asks again);
 *   DISCARDURB  the URB is marked discarded and reaped with -ENOENT;
 *   CLEAR_HALT  ends a stall; CLAIM/RELEASEINTERFACE, GET_CAPABILITIES,
 *               GETDRIVER (-ENODATA: no kernel driver), ... as a kernel.
 * Unplug: the device state goes "gone" at once (pending URBs complete with
 * -ENODEV, new ioctls fail with -ENODEV, as usbfs does); a helper thread
 * sends the "remove" uevent and removes the device, and plugs a new one
 * (device number + 1) later.
 */
#include "usb_emulator/emulated_scanner.h"

#include <errno.h>
#include <sys/ioctl.h>
#include <linux/usbdevice_fs.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <umockdev.h>

#include "pitvol/usb_frame.h"
#include "pitvol/splitmix64.h"
#include "pitvol/usb_scanner.h"

#define EMU_BUS 1

typedef struct frame_info {
  uint64_t off;
  uint32_t len;
  uint32_t seq;
  uint32_t points;
} frame_info_t;

typedef struct urb_entry {
  UMockdevIoctlClient *client; /* not owned: identity only */
  UMockdevIoctlData *urb;      /* owned */
  UMockdevIoctlData *buf;      /* owned, may be NULL */
  gulong client_addr;
  int is_bulk;
  int ready;      /* control URBs: completed at submit */
  int status;
  int actual;
  int discarded;
} urb_entry_t;

struct pv_emu {
  UMockdevTestbed *tb;
  UMockdevIoctlBase *handler;
  GMutex lock;     /* everything below */
  GMutex tb_lock;  /* test bed changes (plug, unplug) */
  GCond cond;
  GThread *helper;
  int quit;
  int want_remove;
  gint64 replug_at_us; /* -1: none */
  int present;        /* device in the test bed (tb_lock) */

  pv_emu_options_t opt;
  uint8_t *stream;
  uint64_t stream_len;
  frame_info_t *frames;
  uint64_t nframes;

  /* serving */
  int plugged;
  unsigned gen;       /* incremented on every plug; clients carry theirs */
  int devnum;
  char syspath[512];
  char devnode[64];
  int streaming;
  int started_once;
  uint64_t pos;
  uint64_t limit;     /* stream_len, or the frame end after STOP */
  uint8_t tail[64];   /* END_OF_SCAN frame after STOP */
  size_t tail_len, tail_pos;
  int halted;
  uint64_t stall_pos; /* UINT64_MAX: none pending */
  uint64_t unplug_pos;
  int resume_pending;
  uint64_t resume_pos;
  gint64 pace_start_us;
  uint64_t pace_sent;
  uint64_t rng;
  GQueue urbs;
  pv_emu_stats_t st;
};

/* ---- helpers ---------------------------------------------------------- */


static void set_err(char *err, size_t cap, const char *msg) {
  if (err != NULL && cap > 0) snprintf(err, cap, "%s", msg);
}

void pv_emu_options_default(pv_emu_options_t *o) {
  memset(o, 0, sizeof *o);
  o->seed = 1;
  o->stall_at_frame = -1;
  o->stall_at_byte = -1;
  o->unplug_at_frame = -1;
  o->replug_after_ms = 200;
}

/* umockdev_in_mock_environment() only says yes once a test bed exists
 * (it looks at $UMOCKDEV_DIR); what matters is the preloaded library. */
int pv_emu_available(void) {
  const char *p = getenv("LD_PRELOAD");
  return p != NULL && strstr(p, "libumockdev-preload") != NULL;
}

/* Index of the frame containing byte pos (or starting at it). */
static uint64_t frame_at(const pv_emu_t *e, uint64_t pos) {
  uint64_t lo = 0, hi = e->nframes;
  while (hi - lo > 1) {
    const uint64_t mid = lo + (hi - lo) / 2;
    if (e->frames[mid].off <= pos) lo = mid;
    else hi = mid;
  }
  return lo;
}

/* The standard USB descriptors of the scanner, as sysfs `descriptors`
 * holds them: device, then configuration 1 with interface 0 (vendor class)
 * and bulk IN endpoint 0x81 (512-byte packets, high speed). */
static const uint8_t kDescriptors[] = {
    /* device */
    18, 0x01, 0x00, 0x02, 0x00, 0x00, 0x00, 64, (uint8_t)(PV_USB_VENDOR_ID & 0xff),
    (uint8_t)(PV_USB_VENDOR_ID >> 8), (uint8_t)(PV_USB_PRODUCT_ID & 0xff),
    (uint8_t)(PV_USB_PRODUCT_ID >> 8), 0x00, 0x01, 0, 0, 0, 1,
    /* configuration: total 9 + 9 + 7 = 25 */
    9, 0x02, 25, 0, 1, 1, 0, 0x80, 50,
    /* interface 0, one endpoint, class 0xFF */
    9, 0x04, (uint8_t)PV_USB_INTERFACE, 0, 1, 0xFF, 0x00, 0x00, 0,
    /* endpoint 0x81 bulk, 512 */
    7, 0x05, (uint8_t)PV_USB_ENDPOINT_IN, 0x02, 0x00, 0x02, 0};

/* ---- test bed: plug and unplug (tb_lock held) ---------------------------- */

static int tb_plug(pv_emu_t *e, char *err, size_t errcap) {
  if (e->present) return 0;
  char busnum[16], devnum[16], devnum3[16], devname[64], dev[32], minor[16];
  g_mutex_lock(&e->lock);
  e->devnum++;
  const int dn = e->devnum;
  g_mutex_unlock(&e->lock);
  snprintf(busnum, sizeof busnum, "%d", EMU_BUS);
  snprintf(devnum, sizeof devnum, "%d", dn);
  snprintf(devnum3, sizeof devnum3, "%03d", dn);
  snprintf(devname, sizeof devname, "/dev/bus/usb/%03d/%03d", EMU_BUS, dn);
  snprintf(minor, sizeof minor, "%d", (EMU_BUS - 1) * 128 + dn - 1);
  snprintf(dev, sizeof dev, "189:%s", minor);
  /* umockdev-record's format: N: creates the device node, H: is a binary
   * attribute (hex). */
  char hex[2 * sizeof kDescriptors + 1];
  for (size_t i = 0; i < sizeof kDescriptors; ++i) snprintf(hex + 2 * i, 3, "%02X", kDescriptors[i]);
  gchar *record = g_strdup_printf(
      "P: /devices/pci0000:00/0000:00:14.0/usb%d/%d-1\n"
      "N: bus/usb/%03d/%s\n"
      "E: DEVNAME=%s\nE: DEVTYPE=usb_device\nE: DRIVER=usb\nE: SUBSYSTEM=usb\n"
      "E: BUSNUM=%03d\nE: DEVNUM=%s\nE: PRODUCT=1209/7050/100\nE: TYPE=0/0/0\n"
      "E: MAJOR=189\nE: MINOR=%s\nE: ID_VENDOR_ID=1209\nE: ID_MODEL_ID=7050\n"
      "A: busnum=%s\\n\nA: devnum=%s\\n\nA: idVendor=1209\\n\nA: idProduct=7050\\n\n"
      "A: bcdDevice=0100\\n\nA: bConfigurationValue=1\\n\nA: bNumConfigurations=1\\n\n"
      "A: bNumInterfaces= 1\\n\nA: bDeviceClass=00\\n\nA: speed=480\\n\n"
      "A: product=pitvol scanner (emulated)\\n\nA: manufacturer=pitvol\\n\nA: dev=%s\\n\n"
      "H: descriptors=%s\n",
      EMU_BUS, EMU_BUS, EMU_BUS, devnum3, devname, EMU_BUS, devnum3, minor, busnum, devnum, dev,
      hex);
  /* The handler goes on the node BEFORE the device appears: adding it
   * announces it ("add" uevent), and a host that opens it at once must
   * find its ioctls served. */
  GError *gerr = NULL;
  if (!umockdev_testbed_attach_ioctl(e->tb, devname, e->handler, &gerr)) {
    if (err != NULL && errcap > 0) {
      snprintf(err, errcap, "umockdev could not attach the ioctl handler to %s: %s", devname,
               gerr != NULL ? gerr->message : "?");
    }
    g_clear_error(&gerr);
    g_free(record);
    return -1;
  }
  g_mutex_lock(&e->lock);
  e->gen++;
  e->plugged = 1;
  e->halted = 0;
  e->streaming = 0;
  g_mutex_unlock(&e->lock);
  GError *perr = NULL;
  const gboolean added = umockdev_testbed_add_from_string(e->tb, record, &perr);
  if (!added) {
    if (err != NULL && errcap > 0) {
      snprintf(err, errcap, "umockdev could not add the scanner device: %s",
               perr != NULL ? perr->message : "?");
    }
    g_clear_error(&perr);
    g_mutex_lock(&e->lock);
    e->plugged = 0;
    g_mutex_unlock(&e->lock);
    (void)umockdev_testbed_detach_ioctl(e->tb, devname, NULL);
    return -1;
  }
  g_free(record);
  gchar *sys = g_strdup_printf("/sys/devices/pci0000:00/0000:00:14.0/usb%d/%d-1", EMU_BUS, EMU_BUS);
  g_mutex_lock(&e->lock);
  snprintf(e->syspath, sizeof e->syspath, "%s", sys);
  snprintf(e->devnode, sizeof e->devnode, "%s", devname);
  g_mutex_unlock(&e->lock);
  g_free(sys);
  e->present = 1;
  umockdev_testbed_uevent(e->tb, e->syspath, "add");
  return 0;
}

static void tb_remove(pv_emu_t *e) {
  if (!e->present) return;
  char sys[512], node[64];
  g_mutex_lock(&e->lock);
  snprintf(sys, sizeof sys, "%s", e->syspath);
  snprintf(node, sizeof node, "%s", e->devnode);
  g_mutex_unlock(&e->lock);
  umockdev_testbed_uevent(e->tb, sys, "remove");
  GError *gerr = NULL;
  (void)umockdev_testbed_detach_ioctl(e->tb, node, &gerr);
  g_clear_error(&gerr);
  umockdev_testbed_remove_device(e->tb, sys);
  e->present = 0;
}

/* e->lock held. The device is gone for the host from now on. */
static void trigger_unplug_locked(pv_emu_t *e) {
  if (!e->plugged) return;
  e->plugged = 0;
  e->st.unplugs++;
  if (e->streaming && e->pos < e->limit) {
    e->resume_pending = 1;
    e->resume_pos = e->frames[frame_at(e, e->pos)].off;
  }
  e->streaming = 0;
  e->halted = 0;
  e->want_remove = 1;
  g_cond_broadcast(&e->cond);
}

static gpointer helper_main(gpointer p) {
  pv_emu_t *e = (pv_emu_t *)p;
  g_mutex_lock(&e->lock);
  while (!e->quit) {
    if (e->want_remove) {
      e->want_remove = 0;
      g_mutex_unlock(&e->lock);
      g_mutex_lock(&e->tb_lock);
      tb_remove(e);
      g_mutex_unlock(&e->tb_lock);
      g_mutex_lock(&e->lock);
      if (e->opt.replug_after_ms >= 0) {
        e->replug_at_us = g_get_monotonic_time() + (gint64)e->opt.replug_after_ms * 1000;
      }
      continue;
    }
    const gint64 now = g_get_monotonic_time();
    if (e->replug_at_us >= 0 && now >= e->replug_at_us) {
      e->replug_at_us = -1;
      g_mutex_unlock(&e->lock);
      g_mutex_lock(&e->tb_lock);
      if (tb_plug(e, NULL, 0) == 0) {
        g_mutex_lock(&e->lock);
        e->st.replugs++;
        g_mutex_unlock(&e->lock);
      }
      g_mutex_unlock(&e->tb_lock);
      g_mutex_lock(&e->lock);
      continue;
    }
    const gint64 until = e->replug_at_us >= 0 ? e->replug_at_us : now + G_USEC_PER_SEC;
    g_cond_wait_until(&e->cond, &e->lock, until);
  }
  g_mutex_unlock(&e->lock);
  return NULL;
}

/* ---- the device's behaviour (e->lock held) ------------------------------- */

static void do_start(pv_emu_t *e) {
  e->st.starts++;
  if (e->resume_pending) {
    e->pos = e->resume_pos;
    e->resume_pending = 0;
  } else if (!e->streaming || (e->pos >= e->limit && e->tail_pos >= e->tail_len)) {
    e->pos = 0; /* a new scan: sequence numbers restart at 0 */
  }
  e->limit = e->stream_len;
  e->tail_len = e->tail_pos = 0;
  e->streaming = 1;
  e->started_once = 1;
  e->halted = 0;
  e->pace_start_us = g_get_monotonic_time();
  e->pace_sent = 0;
}

static void do_stop(pv_emu_t *e) {
  e->st.stops++;
  if (!e->streaming || e->pos >= e->limit) return;
  /* Finish the frame on the wire, then an empty END_OF_SCAN frame. */
  const uint64_t i = frame_at(e, e->pos);
  uint64_t next = i;
  if (e->frames[i].off < e->pos) {
    e->limit = e->frames[i].off + e->frames[i].len;
    next = i + 1;
  } else {
    e->limit = e->pos;
  }
  pv_usb_frame_header_t h;
  memset(&h, 0, sizeof h);
  h.version = PV_USB_FRAME_VERSION;
  h.flags = PV_USB_FLAG_END_OF_SCAN;
  h.point_count = 0;
  h.sequence = next > 0 ? e->frames[next - 1].seq + 1u : 0u;
  e->tail_len = pv_usb_frame_encode(e->tail, sizeof e->tail, &h, NULL);
  e->tail_pos = 0;
}

/* A control request (setup packet fields). 0 or a negative errno. */
static int do_control(pv_emu_t *e, uint8_t type, uint8_t req) {
  if (type == PV_USB_REQUEST_TYPE_OUT && req == PV_USB_REQUEST_START) {
    do_start(e);
    return 0;
  }
  if (type == PV_USB_REQUEST_TYPE_OUT && req == PV_USB_REQUEST_STOP) {
    do_stop(e);
    return 0;
  }
  if ((type == 0x00 && req == 0x09) || (type == 0x01 && req == 0x0B)) return 0; /* SET_CONFIG/IF */
  return -EPIPE; /* unsupported request: the control endpoint stalls */
}

static uint64_t pace_budget(pv_emu_t *e) {
  if (e->opt.bytes_per_interval == 0) return UINT64_MAX;
  const uint32_t iv = e->opt.interval_ms > 0 ? e->opt.interval_ms : 1;
  const gint64 el_ms = (g_get_monotonic_time() - e->pace_start_us) / 1000;
  const uint64_t allowed = ((uint64_t)el_ms / iv + 1u) * e->opt.bytes_per_interval;
  return allowed > e->pace_sent ? allowed - e->pace_sent : 0;
}

/* Completes bulk URB u now if the device has something to say: returns 1
 * with u->status/actual set, or 0 (nothing yet). */
static int serve_bulk(pv_emu_t *e, urb_entry_t *u, int live) {
  struct usbdevfs_urb *urb = (struct usbdevfs_urb *)u->urb->data;
  if (!live) {
    u->status = -ENODEV;
    u->actual = 0;
    e->st.urbs_nodev++;
    return 1;
  }
  if (e->halted) {
    u->status = -EPIPE;
    u->actual = 0;
    e->st.urbs_stalled++;
    return 1;
  }
  if (!e->streaming) return 0;
  if (e->pos < e->limit) {
    if (e->pos >= e->stall_pos) {
      e->stall_pos = UINT64_MAX;
      e->halted = 1;
      u->status = -EPIPE;
      u->actual = 0;
      e->st.urbs_stalled++;
      return 1;
    }
    if (e->pos >= e->unplug_pos) {
      e->unplug_pos = UINT64_MAX;
      trigger_unplug_locked(e);
      u->status = -ENODEV;
      u->actual = 0;
      e->st.urbs_nodev++;
      return 1;
    }
    uint64_t n = (uint64_t)(urb->buffer_length > 0 ? urb->buffer_length : 0);
    if (u->buf == NULL) n = 0;
    uint64_t end = e->limit;
    if (e->stall_pos < end) end = e->stall_pos;
    if (e->unplug_pos < end) end = e->unplug_pos;
    if (end - e->pos < n) n = end - e->pos;
    const uint64_t budget = pace_budget(e);
    if (budget < n) n = budget;
    if (n == 0) return 0;
    if (e->opt.short_reads) n = 1 + pv_splitmix64_next(&e->rng) % n;
    memcpy(u->buf->data, e->stream + e->pos, (size_t)n);
    e->pos += n;
    e->pace_sent += n;
    e->st.bytes_served += n;
    e->st.urbs_bulk++;
    u->status = 0;
    u->actual = (int)n;
    return 1;
  }
  if (e->tail_pos < e->tail_len) {
    size_t n = e->tail_len - e->tail_pos;
    if (u->buf == NULL || (size_t)urb->buffer_length < n) return 0;
    memcpy(u->buf->data, e->tail + e->tail_pos, n);
    e->tail_pos += n;
    e->st.bytes_served += n;
    e->st.urbs_bulk++;
    u->status = 0;
    u->actual = (int)n;
    return 1;
  }
  return 0; /* all sent: the host's URBs wait */
}

static void free_entry(urb_entry_t *u) {
  if (u->buf != NULL) g_object_unref(u->buf);
  if (u->urb != NULL) g_object_unref(u->urb);
  g_free(u);
}

/* The URB of this client to complete now, removed from the queue; NULL if
 * none can complete yet. */
static urb_entry_t *pick_reapable(pv_emu_t *e, UMockdevIoctlClient *c, int live) {
  for (GList *l = e->urbs.head; l != NULL; l = l->next) {
    urb_entry_t *u = (urb_entry_t *)l->data;
    if (u->client != c) continue;
    if (u->discarded) {
      u->status = -ENOENT;
      u->actual = 0;
      e->st.urbs_discarded++;
      g_queue_delete_link(&e->urbs, l);
      return u;
    }
    if (u->ready) {
      g_queue_delete_link(&e->urbs, l);
      return u;
    }
  }
  for (GList *l = e->urbs.head; l != NULL; l = l->next) {
    urb_entry_t *u = (urb_entry_t *)l->data;
    if (u->client != c || !u->is_bulk) continue;
    if (!serve_bulk(e, u, live)) return NULL; /* FIFO: the oldest first */
    g_queue_delete_link(&e->urbs, l);
    return u;
  }
  return NULL;
}

/* ---- the ioctl handler (umockdev worker thread) -------------------------- */

static gboolean on_ioctl(UMockdevIoctlBase *handler, UMockdevIoctlClient *client, gpointer user) {
  (void)handler;
  pv_emu_t *e = (pv_emu_t *)user;
  const gulong req = umockdev_ioctl_client_get_request(client);
  UMockdevIoctlData *arg = umockdev_ioctl_client_get_arg(client);
  GError *gerr = NULL;
  glong ret = 0;
  gint eno = 0;

  g_mutex_lock(&e->lock);
  unsigned cgen = GPOINTER_TO_UINT(g_object_get_data(G_OBJECT(client), "pv-emu-gen"));
  if (cgen == 0) {
    cgen = e->gen;
    g_object_set_data(G_OBJECT(client), "pv-emu-gen", GUINT_TO_POINTER(cgen));
  }
  const int live = e->plugged && cgen == e->gen;

  if (req == USBDEVFS_REAPURB || req == USBDEVFS_REAPURBNDELAY) {
    UMockdevIoctlData *p = umockdev_ioctl_data_resolve(arg, 0, sizeof(void *), &gerr);
    urb_entry_t *u = p != NULL ? pick_reapable(e, client, live) : NULL;
    if (u == NULL) {
      ret = -1;
      eno = p == NULL ? EFAULT : (live ? EAGAIN : ENODEV);
    } else {
      struct usbdevfs_urb *urb = (struct usbdevfs_urb *)u->urb->data;
      urb->status = u->status;
      urb->actual_length = u->actual;
      if (!umockdev_ioctl_data_set_ptr(p, 0, u->urb)) {
        ret = -1;
        eno = EFAULT;
      }
      free_entry(u);
    }
    if (p != NULL) g_object_unref(p);
  } else if (!live) {
    ret = -1;
    eno = ENODEV;
  } else {
    switch (req) {
      case USBDEVFS_SUBMITURB: {
        UMockdevIoctlData *ud =
            umockdev_ioctl_data_resolve(arg, 0, sizeof(struct usbdevfs_urb), &gerr);
        if (ud == NULL) {
          ret = -1;
          eno = EFAULT;
          break;
        }
        struct usbdevfs_urb *urb = (struct usbdevfs_urb *)ud->data;
        urb_entry_t *u = g_new0(urb_entry_t, 1);
        u->client = client;
        u->urb = ud;
        u->client_addr = ud->client_addr;
        if (urb->buffer_length > 0) {
          u->buf = umockdev_ioctl_data_resolve(ud, offsetof(struct usbdevfs_urb, buffer),
                                               (gsize)urb->buffer_length, &gerr);
        }
        if (urb->type == USBDEVFS_URB_TYPE_CONTROL && u->buf != NULL && urb->buffer_length >= 8) {
          const uint8_t *setup = u->buf->data;
          const int r = do_control(e, setup[0], setup[1]);
          u->ready = 1;
          u->status = r;
          u->actual = 0;
          g_queue_push_tail(&e->urbs, u);
        } else if (urb->type == USBDEVFS_URB_TYPE_BULK && urb->endpoint == PV_USB_ENDPOINT_IN) {
          u->is_bulk = 1;
          g_queue_push_tail(&e->urbs, u);
        } else {
          free_entry(u);
          ret = -1;
          eno = EINVAL;
        }
        break;
      }
      case USBDEVFS_DISCARDURB: {
        const gulong addr = arg->data_len >= (gint)sizeof(gulong) ? *(const gulong *)arg->data : 0;
        ret = -1;
        eno = EINVAL;
        for (GList *l = e->urbs.head; l != NULL; l = l->next) {
          urb_entry_t *u = (urb_entry_t *)l->data;
          if (u->client == client && u->client_addr == addr && !u->discarded) {
            u->discarded = 1;
            ret = 0;
            eno = 0;
            break;
          }
        }
        break;
      }
      case USBDEVFS_CONTROL: {
        UMockdevIoctlData *cd =
            umockdev_ioctl_data_resolve(arg, 0, sizeof(struct usbdevfs_ctrltransfer), &gerr);
        if (cd == NULL) {
          ret = -1;
          eno = EFAULT;
          break;
        }
        const struct usbdevfs_ctrltransfer *ct = (const struct usbdevfs_ctrltransfer *)cd->data;
        const int r = do_control(e, ct->bRequestType, ct->bRequest);
        ret = r < 0 ? -1 : 0;
        eno = r < 0 ? -r : 0;
        g_object_unref(cd);
        break;
      }
      case USBDEVFS_GET_CAPABILITIES: {
        UMockdevIoctlData *cd = umockdev_ioctl_data_resolve(arg, 0, sizeof(guint32), &gerr);
        if (cd == NULL) {
          ret = -1;
          eno = EFAULT;
          break;
        }
        const guint32 caps = USBDEVFS_CAP_BULK_CONTINUATION | USBDEVFS_CAP_NO_PACKET_SIZE_LIM |
                             USBDEVFS_CAP_REAP_AFTER_DISCONNECT | USBDEVFS_CAP_ZERO_PACKET |
                             USBDEVFS_CAP_BULK_SCATTER_GATHER;
        memcpy(cd->data, &caps, sizeof caps);
        g_object_unref(cd);
        break;
      }
      case USBDEVFS_CLEAR_HALT:
        e->halted = 0;
        e->st.clear_halts++;
        break;
      case USBDEVFS_CLAIMINTERFACE:
      case USBDEVFS_RELEASEINTERFACE:
      case USBDEVFS_SETINTERFACE:
      case USBDEVFS_SETCONFIGURATION:
      case USBDEVFS_RESET:
      case USBDEVFS_RESETEP:
      case USBDEVFS_DISCONNECT_CLAIM:
        break;
      case USBDEVFS_GETDRIVER:
      case USBDEVFS_IOCTL:
        ret = -1;
        eno = ENODATA; /* no kernel driver bound */
        break;
      case USBDEVFS_GET_SPEED:
        ret = 3; /* USB_SPEED_HIGH */
        break;
      default:
        ret = -1;
        eno = ENOTTY;
        break;
    }
  }
  g_mutex_unlock(&e->lock);
  g_clear_error(&gerr);
  umockdev_ioctl_client_complete(client, ret, eno);
  return TRUE;
}

/* ---- construction ------------------------------------------------------- */

/* Indexes the source frames and builds the served stream with the faults. */
static int build_stream(pv_emu_t *e, const uint8_t *src, size_t len, char *err, size_t errcap) {
  uint64_t nsrc = 0;
  size_t at = 0;
  /* pass 1: count and check */
  while (at < len) {
    pv_usb_frame_header_t h;
    if (pv_usb_frame_parse_header(src + at, len - at, &h) != PV_USB_PARSE_OK) {
      if (err != NULL) snprintf(err, errcap, "not a USB frame at byte %zu of the source", at);
      return -1;
    }
    const size_t flen = PV_USB_FRAME_BYTES(h.point_count);
    if (flen > len - at) {
      if (err != NULL) snprintf(err, errcap, "the source ends inside the frame at byte %zu", at);
      return -1;
    }
    at += flen;
    nsrc++;
    e->st.points_in += h.point_count;
  }
  if (nsrc == 0) {
    set_err(err, errcap, "the source holds no frames");
    return -1;
  }
  e->st.frames_in = nsrc;
  /* worst case every frame doubled */
  e->stream = (uint8_t *)malloc(2 * len);
  e->frames = (frame_info_t *)malloc(sizeof(frame_info_t) * (size_t)(2 * nsrc));
  if (e->stream == NULL || e->frames == NULL) {
    set_err(err, errcap, "out of memory");
    return -1;
  }
  uint64_t rng = e->opt.seed ^ 0x5049544D56ull;
  at = 0;
  for (uint64_t i = 0; i < nsrc; ++i) {
    pv_usb_frame_header_t h;
    /* Every frame passed this parse when they were counted above. */
    const pv_usb_parse_t parsed = pv_usb_frame_parse_header(src + at, len - at, &h);
    (void)parsed;
    const size_t flen = PV_USB_FRAME_BYTES(h.point_count);
    const int last = i + 1 == nsrc;
    const double r_drop = pv_splitmix64_unit(&rng), r_dup = pv_splitmix64_unit(&rng),
                 r_bad = pv_splitmix64_unit(&rng);
    if (!last && r_drop < e->opt.drop_rate) {
      e->st.frames_dropped++;
      e->st.points_dropped += h.point_count;
      at += flen;
      continue;
    }
    const int copies = (!last && r_dup < e->opt.duplicate_rate) ? 2 : 1;
    const int corrupt = !last && r_bad < e->opt.corrupt_rate;
    for (int c = 0; c < copies; ++c) {
      frame_info_t *f = &e->frames[e->nframes++];
      f->off = e->stream_len;
      f->len = (uint32_t)flen;
      f->seq = h.sequence;
      f->points = h.point_count;
      memcpy(e->stream + e->stream_len, src + at, flen);
      if (corrupt && c == 0) e->stream[e->stream_len + flen - 1] ^= 0x5Au; /* CRC byte */
      e->stream_len += flen;
    }
    if (corrupt) {
      e->st.frames_corrupted++;
      e->st.points_corrupted += h.point_count;
    }
    if (copies == 2) e->st.frames_duplicated++;
    at += flen;
  }
  e->st.frames_out = e->nframes;
  e->st.bytes_out = e->stream_len;
  e->limit = e->stream_len;
  e->stall_pos = UINT64_MAX;
  e->unplug_pos = UINT64_MAX;
  if (e->opt.stall_at_byte >= 0 && (uint64_t)e->opt.stall_at_byte < e->stream_len) {
    e->stall_pos = (uint64_t)e->opt.stall_at_byte;
  } else if (e->opt.stall_at_frame >= 0 && (uint64_t)e->opt.stall_at_frame < e->nframes) {
    e->stall_pos = e->frames[e->opt.stall_at_frame].off;
  }
  if (e->opt.unplug_at_frame >= 0 && (uint64_t)e->opt.unplug_at_frame < e->nframes) {
    const frame_info_t *f = &e->frames[e->opt.unplug_at_frame];
    e->unplug_pos = f->off + f->len / 2;
  }
  return 0;
}

int pv_emu_create_from_memory(pv_emu_t **out, const uint8_t *bytes, size_t len,
                              const pv_emu_options_t *o, char *err, size_t errcap) {
  *out = NULL;
  if (!pv_emu_available()) {
    set_err(err, errcap, "not running under umockdev-wrapper (LD_PRELOAD of libumockdev-preload)");
    return -1;
  }
  pv_emu_t *e = g_new0(pv_emu_t, 1);
  g_mutex_init(&e->lock);
  g_mutex_init(&e->tb_lock);
  g_cond_init(&e->cond);
  g_queue_init(&e->urbs);
  e->replug_at_us = -1;
  e->devnum = 1; /* the first device is 001/002 (001 is the root hub) */
  if (o != NULL) e->opt = *o;
  else pv_emu_options_default(&e->opt);
  e->rng = e->opt.seed * 0x2545F4914F6CDD1Dull + 7u;
  if (build_stream(e, bytes, len, err, errcap) != 0) {
    pv_emu_destroy(e);
    return -1;
  }
  e->tb = umockdev_testbed_new();
  e->handler = umockdev_ioctl_base_new();
  g_signal_connect(e->handler, "handle-ioctl", G_CALLBACK(on_ioctl), e);
  g_mutex_lock(&e->tb_lock);
  const int r = tb_plug(e, err, errcap);
  g_mutex_unlock(&e->tb_lock);
  if (r != 0) {
    pv_emu_destroy(e);
    return -1;
  }
  e->helper = g_thread_new("pv-emu-helper", helper_main, e);
  *out = e;
  return 0;
}

/* A frame stream file, whole (g_free it); NULL with err filled on failure. */
static gchar *read_frames(const char *frames_path, gsize *len, char *err, size_t errcap) {
  gchar *data = NULL;
  GError *gerr = NULL;
  if (!g_file_get_contents(frames_path, &data, len, &gerr)) {
    if (err != NULL) snprintf(err, errcap, "%s", gerr != NULL ? gerr->message : "cannot read");
    g_clear_error(&gerr);
    return NULL;
  }
  return data;
}

int pv_emu_create_from_file(pv_emu_t **out, const char *frames_path, const pv_emu_options_t *o,
                            char *err, size_t errcap) {
  gsize len = 0;
  *out = NULL;
  gchar *data = read_frames(frames_path, &len, err, errcap);
  if (data == NULL) return -1;
  const int r = pv_emu_create_from_memory(out, (const uint8_t *)data, len, o, err, errcap);
  g_free(data);
  return r;
}

int pv_emu_load_memory(pv_emu_t *e, const uint8_t *bytes, size_t len, char *err, size_t errcap) {
  g_mutex_lock(&e->lock);
  const int busy = e->streaming && !(e->pos >= e->limit && e->tail_pos >= e->tail_len);
  if (busy) {
    g_mutex_unlock(&e->lock);
    set_err(err, errcap, "a scan is being served; load the next one after it ended");
    return -1;
  }
  /* The stream statistics describe the loaded stream; the transfer ones
   * (URBs, starts, stops, plugs) keep counting. */
  const pv_emu_stats_t old_st = e->st;
  uint8_t *old_stream = e->stream;
  frame_info_t *old_frames = e->frames;
  const uint64_t old_len = e->stream_len, old_n = e->nframes;
  e->stream = NULL;
  e->frames = NULL;
  e->stream_len = e->nframes = 0;
  e->st.frames_in = e->st.points_in = e->st.frames_out = e->st.bytes_out = 0;
  e->st.frames_corrupted = e->st.frames_dropped = e->st.points_dropped = 0;
  e->st.points_corrupted = e->st.frames_duplicated = 0;
  if (build_stream(e, bytes, len, err, errcap) != 0) {
    free(e->stream);
    free(e->frames);
    e->stream = old_stream;
    e->frames = old_frames;
    e->stream_len = old_len;
    e->nframes = old_n;
    e->st = old_st;
    g_mutex_unlock(&e->lock);
    return -1;
  }
  free(old_stream);
  free(old_frames);
  e->streaming = 0; /* the next START serves the new stream from its start */
  e->pos = 0;
  e->tail_len = e->tail_pos = 0;
  e->resume_pending = 0;
  g_mutex_unlock(&e->lock);
  return 0;
}

int pv_emu_load_file(pv_emu_t *e, const char *frames_path, char *err, size_t errcap) {
  gsize len = 0;
  gchar *data = read_frames(frames_path, &len, err, errcap);
  if (data == NULL) return -1;
  const int r = pv_emu_load_memory(e, (const uint8_t *)data, len, err, errcap);
  g_free(data);
  return r;
}

int pv_emu_unplug(pv_emu_t *e) {
  g_mutex_lock(&e->lock);
  trigger_unplug_locked(e);
  g_mutex_unlock(&e->lock);
  return 0;
}

int pv_emu_replug(pv_emu_t *e) {
  g_mutex_lock(&e->lock);
  const int pending_remove = e->want_remove;
  e->want_remove = 0;
  e->replug_at_us = -1;
  const int was_plugged = e->plugged;
  g_mutex_unlock(&e->lock);
  if (was_plugged) return 0;
  g_mutex_lock(&e->tb_lock);
  if (pending_remove || e->present) tb_remove(e);
  const int r = tb_plug(e, NULL, 0);
  g_mutex_unlock(&e->tb_lock);
  if (r == 0) {
    g_mutex_lock(&e->lock);
    e->st.replugs++;
    g_mutex_unlock(&e->lock);
  }
  return r;
}

void pv_emu_stats(pv_emu_t *e, pv_emu_stats_t *out) {
  g_mutex_lock(&e->lock);
  *out = e->st;
  out->plugged = e->plugged;
  out->finished = e->started_once && e->pos >= e->limit && e->tail_pos >= e->tail_len;
  g_mutex_unlock(&e->lock);
}

uint64_t pv_emu_frame_count(pv_emu_t *e) { return e->nframes; }

uint64_t pv_emu_points_before_frame(pv_emu_t *e, uint64_t n) {
  uint64_t p = 0;
  for (uint64_t i = 0; i < n && i < e->nframes; ++i) p += e->frames[i].points;
  return p;
}

void pv_emu_destroy(pv_emu_t *e) {
  if (e == NULL) return;
  if (e->helper != NULL) {
    g_mutex_lock(&e->lock);
    e->quit = 1;
    g_cond_broadcast(&e->cond);
    g_mutex_unlock(&e->lock);
    g_thread_join(e->helper);
  }
  if (e->tb != NULL) {
    g_mutex_lock(&e->tb_lock);
    tb_remove(e);
    g_mutex_unlock(&e->tb_lock);
  }
  urb_entry_t *u;
  while ((u = (urb_entry_t *)g_queue_pop_head(&e->urbs)) != NULL) free_entry(u);
  if (e->handler != NULL) g_object_unref(e->handler);
  if (e->tb != NULL) g_object_unref(e->tb);
  free(e->stream);
  free(e->frames);
  g_cond_clear(&e->cond);
  g_mutex_clear(&e->tb_lock);
  g_mutex_clear(&e->lock);
  g_free(e);
}
